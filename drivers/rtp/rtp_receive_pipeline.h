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
inline constexpr const char* kDepayloader = "depay";
inline constexpr const char* kDecoder = "dec";
inline constexpr const char* kAppSink = "sink";
inline constexpr const char* kSrtpDecoder = "srtpdec";
inline constexpr const char* kNetsim = "netsim";
}  // namespace rtp_elements

/// udpsrc (RTP) [→ netsim] → rtpbin (jitter buffer, NACK/RTX) → rtph264depay (asks for a key
/// frame on loss) → avdec_h264 (one thread: no frame-threading delay) → videoconvert → RGBA →
/// appsink (no clock sync, newest frame only); udpsrc (RTCP) → rtpbin → multiudpsink (RTCP
/// receiver reports and feedback to wherever the sender's RTCP comes from). With a key, srtpdec
/// sits between both udpsrcs and rtpbin; the key is not in the description (the camera hands it
/// to srtpdec's request-key signal), so the description can be shown.
std::string receive_pipeline_description(const RtpReceiveConfig& c);

}  // namespace hd::drivers
