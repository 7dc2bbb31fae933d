#pragma once
// A pure parser of one RTP packet (RFC 3550) and its RFC 8285 header extension elements: what the
// network camera checks every packet with before GStreamer sees it, fuzzed with mutated packets.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace hd::drivers {

/// Why a packet was refused (the counters are indexed by it).
enum class RtpPacketError : uint8_t {
  kNone,
  kTooShort,          ///< shorter than the 12-byte fixed header
  kBadVersion,        ///< version field not 2
  kCsrcOverrun,       ///< the CSRC list runs past the packet's end
  kExtensionOverrun,  ///< the header extension runs past the packet's end
  kBadPadding,        ///< padding count 0 or larger than what follows the header
  kBadExtension,      ///< an RFC 8285 element runs past its block, or uses the reserved id 15
  // The stream (RtpCamera): rtpbin makes a pad for every new SSRC and payload type, and one that
  // nothing is linked to stops the pipeline, so one such packet would restart the camera.
  kOtherPayloadType,  ///< neither the stream's payload type nor its RTX payload type
  kOtherSsrc,         ///< another SSRC while the stream's own is live (a sender restarting waits)
  // The stream's own SSRC with numbers no live sender sends (RtpStreamGuard): rtpjitterbuffer
  // would ask for every packet of a wild sequence gap again and stop passing packets on.
  kSequenceJump,  ///< sequence number too far ahead of or behind the stream's (not confirmed)
  kRtpTimeJump,   ///< RTP time too far from the stream's for the time that passed
  // The H.264 payload (RFC 6184, check_h264_payload in h264_payload.h):
  kH264Empty,         ///< no payload, or its forbidden bit set
  kH264BadType,       ///< NAL type 0, 30, 31 (undefined), or STAP-B, MTAP, FU-B (mode 1 has none)
  kH264BadAggregate,  ///< a STAP-A whose NAL unit sizes do not fill it exactly, or are 0
  kH264BadFragment,   ///< a FU-A shorter than 3 bytes, or with both start and end bits
  // ULP FEC (RFC 5109), when the station takes it (RtpCamera::check_payload):
  kFecTooShort,  ///< shorter than the FEC header and one level header (after an RTX's OSN)
  kCount
};

std::string_view to_string(RtpPacketError e);

/// The fields of a packet that parsed; the spans point into the caller's bytes.
struct RtpPacketView {
  uint8_t payload_type = 0;
  bool marker = false;
  uint16_t sequence = 0;
  uint32_t timestamp = 0;  ///< in the payload's clock (90 kHz for video)
  uint32_t ssrc = 0;
  /// 0xBEDE for RFC 8285 one-byte elements, 0x1000..0x100F for two-byte ones, else another
  /// profile's extension (kept, its elements are not interpreted); 0 without extension.
  uint16_t extension_profile = 0;
  bool has_extension = false;
  std::span<const uint8_t> extension;  ///< the extension block after its 4-byte header
  std::span<const uint8_t> payload;    ///< without padding
};

/// Parses the fixed header, CSRCs, header extension (and checks its RFC 8285 elements when it is
/// one) and padding. Never reads outside `packet`.
RtpPacketError parse_rtp_packet(std::span<const uint8_t> packet, RtpPacketView& out);

/// The data of RFC 8285 element `id` (1..14 one-byte, 1..255 two-byte) in a parsed packet; false
/// when the packet has no such element. Call only on a packet parse_rtp_packet accepted.
bool find_rtp_extension(const RtpPacketView& p, uint8_t id, std::span<const uint8_t>& data);

/// The RFC 8285 elements of a one-byte-form block (`one_byte_block`, after 0xBEDE and its length)
/// rewritten in the two-byte form (profile 0x1000, RFC 8285 4.3) with element `extra_id` =
/// `extra` appended, zero-padded to whole 32-bit words, into `out`: how an element longer than 16
/// bytes joins a packet that already carries one-byte elements (one packet has one form). Returns
/// the bytes written (a multiple of 4); 0 when the block is malformed, `extra` is longer than 255
/// bytes, `extra_id` is 0, or `out` is too small.
std::size_t to_two_byte_block(std::span<const uint8_t> one_byte_block, uint8_t extra_id,
                              std::span<const uint8_t> extra, std::span<uint8_t> out);

}  // namespace hd::drivers
