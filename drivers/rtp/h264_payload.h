#pragma once
// A pure check of an RTP H.264 payload (RFC 6184, packetization mode 1) before GStreamer's
// depayloader sees it: rtph264depay 1.22 reads past a 1-byte FU-A (and crashes on it) and posts an
// error (which restarts the camera) on an MTAP, so the station refuses them first.

#include <cstdint>
#include <span>

#include "drivers/rtp/rtp_packet.h"

namespace hd::drivers {

/// kNone for a single NAL unit (types 1..23), a STAP-A (24) whose 16-bit sizes cover it exactly
/// with NAL units of at least one byte, or a FU-A (28) of at least 3 bytes (indicator, header,
/// data) without both start and end bits; otherwise why not (RtpPacketError::kH264*).
RtpPacketError check_h264_payload(std::span<const uint8_t> payload);

/// The same for a retransmission (RFC 4588 §4): the original sequence number (2 bytes), then the
/// original payload, which is what must pass check_h264_payload. Shorter than 3 bytes: kH264Empty.
RtpPacketError check_h264_rtx_payload(std::span<const uint8_t> payload);

}  // namespace hd::drivers
