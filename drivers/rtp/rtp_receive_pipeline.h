#pragma once
// The network camera's GStreamer pipeline as data: a gst_parse_launch description built from the
// named settings of an RtpReceiveConfig.

#include <string>

#include "drivers/rtp/rtp_receive_config.h"

namespace hd::drivers {

/// Element names the camera looks up in the parsed pipeline.
namespace rtp_elements {
inline constexpr const char* kRtpBin = "rtpbin";
inline constexpr const char* kRtpSource = "rtp_src";
inline constexpr const char* kRtcpSource = "rtcp_src";
inline constexpr const char* kRtcpSink = "rtcp_sink";
inline constexpr const char* kDecodeQueue = "decodeq";  ///< jitter buffer → queue → depay
inline constexpr const char* kDepayloader = "depay";
inline constexpr const char* kDecoder = "dec";
inline constexpr const char* kAppSink = "sink";
inline constexpr const char* kSrtpDecoder = "srtpdec";
inline constexpr const char* kSrtpEncoder = "srtpenc";  ///< the station's own RTCP
inline constexpr const char* kNetsim = "netsim";
inline constexpr const char* kRtxReceive = "rtxreceive";
inline constexpr const char* kFecDecoder = "fecdec";  ///< inside rtpbin, behind the jitter buffer
}  // namespace rtp_elements

/// udpsrc (RTP; kernel buffer receive_buffer_bytes) [→ netsim] → rtpbin (jitter buffer,
/// NACK/RTX) → queue (a thread of its own for what follows) → rtph264depay (asks for a key frame on
/// loss) → avdec_h264 (one thread: no frame-threading delay) → appsink (no clock sync, newest
/// frame only; RtpCamera converts to RGBA straight into its mailbox); udpsrc (RTCP) → rtpbin →
/// multiudpsink (RTCP receiver reports and feedback to wherever the sender's RTCP comes from). With
/// a key, srtpdec sits between both udpsrcs and rtpbin; the key is not in the description (the
/// camera hands it to srtpdec's request-key signal), so the description can be shown.
///
/// The media chain (udpsrc [→ srtpdec] [→ netsim]) ends unlinked: the camera links
/// receive_media_link() to rtpbin.recv_rtp_sink_0 after connecting its request-aux-receiver
/// handler, which rtpbin calls when that pad is requested (so it cannot be in the description).
std::string receive_pipeline_description(const RtpReceiveConfig& c);
/// The jitter buffer's latency when the pipeline starts, ms (the measured budget's start value
/// with jitter_buffer_auto, else jitter_buffer_latency_ms).
int initial_latency_ms(const RtpReceiveConfig& c);

/// The part after rtpbin, as receive_pipeline_description() builds it: the depayloader
/// (rtph264depay, named kDepayloader) and the decoder (avdec_h264 named kDecoder, its own raw
/// format: RtpCamera converts to RGBA into its mailbox), each a gst_parse_launch fragment (the
/// fuzz test feeds them directly).
std::string depayloader_description();
std::string decoder_description();
/// The element and pad that feed rtpbin.recv_rtp_sink_0. netsim sits before rtpbin (and so
/// before the RTX receiver): it drops retransmissions with the same probability as the
/// originals, and a dropped original can still be repaired.
struct MediaLink {
  const char* element;
  const char* pad;
};
MediaLink receive_media_link(const RtpReceiveConfig& c);

/// rtpbin's aux receiver for RTX (RFC 4588, SSRC-multiplexed), when c.retransmission:
/// rtprtxreceive turning rtx_payload_type back into payload_type. It sits between the session
/// and the jitter buffers, where it sees the jitter buffer's retransmission requests (and so
/// learns which SSRC repairs which). A plain sender's packets pass through untouched.
std::string rtx_receive_description(const RtpReceiveConfig& c);

}  // namespace hd::drivers
