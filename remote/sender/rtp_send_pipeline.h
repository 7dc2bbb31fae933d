#pragma once
// The remote site's GStreamer send pipeline for one camera as data: a gst_parse_launch
// description built from the named settings of an RtpSendConfig.

#include <gst/gst.h>

#include <string>

#include "remote/sender/rtp_send_config.h"

namespace hd::remote {

namespace send_elements {
inline constexpr const char* kAppSource = "src";
inline constexpr const char* kEncoder = "enc";
inline constexpr const char* kPayloader = "pay";
inline constexpr const char* kRtpBin = "rtpbin";
inline constexpr const char* kSrtpEncoder = "srtpenc";
inline constexpr const char* kRtcpOut = "rtcp_out";
inline constexpr const char* kRtpOut = "rtp_out";
inline constexpr const char* kRtcpIn = "rtcp_in";
inline constexpr const char* kSrtcpDecoder = "srtcpdec";  ///< the station's RTCP, with a key
inline constexpr const char* kRtxSend = "rtxsend";
inline constexpr const char* kFecEncoder = "fecenc";
}  // namespace send_elements

/// appsrc (the encoder's format, I420 for x264enc, which push() converts each RGBA frame to;
/// live, the newest 2 frames) → x264enc (zerolatency, ultrafast, no B-frames, key frame every
/// key_int_frames, VBV one frame) → rtph264pay (SPS/PPS with every IDR) → rtpbin (RTCP sender reports) → [srtpenc] → udpsink host:port; RTCP →
/// [srtpenc] → udpsink port + 1; the station's RTCP → [srtpdec] → rtpbin. The key is not in the
/// description (RtpSender sets it).
/// The payloader's src pad is left unlinked: RtpSender links it to rtpbin's send_rtp_sink_0
/// once it can answer rtpbin's request-aux-sender signal, which rtpbin emits when that pad is
/// requested (gst_parse_launch would request it before any handler could be connected).
std::string send_pipeline_description(const RtpSendConfig& c);

/// rtpbin's aux sender for RTX (RFC 4588, SSRC-multiplexed), when c.retransmission: rtprtxsend
/// keeping rtx_history_ms of packets, payload_type → rtx_payload_type (a random RTX SSRC). The
/// RTX packets carry the original's header extensions (capture time, camera state).
std::string rtx_send_description(const RtpSendConfig& c);

/// rtpbin's FEC encoder, when c.fec_percentage > 0: rtpulpfecenc protecting each frame's packets
/// (multipacket: the marker bit closes a set) with c.fec_percentage % of FEC packets.
GstElement* make_fec_encoder(const RtpSendConfig& c);

}  // namespace hd::remote
