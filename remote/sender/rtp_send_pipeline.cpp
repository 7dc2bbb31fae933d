#include "remote/sender/rtp_send_pipeline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "drivers/rtp/srtp_elements.h"
#include "remote/sender/h264_encoder.h"

namespace hd::remote {

int RtpSendConfig::key_int_frames() const {
  return std::max(1, static_cast<int>(std::lround(key_interval_s * rate_hz)));
}

int RtpSendConfig::vbv_buffer_ms() const {
  return std::max(1, static_cast<int>(std::ceil(1000.0 / rate_hz)));
}

std::string send_pipeline_description(const RtpSendConfig& c) {
  using namespace send_elements;
  const int fps_n = static_cast<int>(std::lround(c.rate_hz * 1000.0));
  std::string d;
  // AVPF (RFC 4585): the station's NACK and PLI are acted on as they come. rtpsession would
  // overwrite the ntp-64 element with its own NTP time of the buffer's running time
  // (update-ntp64-header-ext, default true in 1.22): the capture time is push()'s.
  d += std::string("rtpbin name=") + kRtpBin + " rtp-profile=avpf update-ntp64-header-ext=false ";
  d += std::string("appsrc name=") + kAppSource +
       " is-live=true format=time do-timestamp=false max-buffers=2 leaky-type=downstream "
       "caps=video/x-raw,format=" +
       h264_encoder_input_format(c.encoder) + ",width=" + std::to_string(c.width_px) +
       ",height=" + std::to_string(c.height_px) + ",framerate=" + std::to_string(fps_n) + "/1000 ";
  if (c.intra_refresh && c.encoder != kSoftwareH264Encoder)
    throw std::invalid_argument("intra refresh needs x264enc, not " + c.encoder);
  d += "! " +
       h264_encoder_description(c.encoder, c.bitrate_kbps, c.key_int_frames(), c.vbv_buffer_ms(),
                                c.intra_refresh) +
       " ";
  d += std::string("! rtph264pay name=") + kPayloader +
       " config-interval=-1 pt=" + std::to_string(c.payload_type) +
       " mtu=" + std::to_string(c.mtu_bytes) + " ";
  // The payloader is linked to rtpbin.send_rtp_sink_0 by RtpSender after it has answered
  // rtpbin's request-aux-sender (the request is made when that pad is), see send_media_link.
  const std::string enc = kSrtpEncoder;
  if (c.srtp_key) d += "srtpenc name=" + enc + " " + drivers::kSrtpEncoderCiphers + " ";
  d += std::string(kRtpBin) + ".send_rtp_src_0 ! " +
       (c.srtp_key ? enc + ".rtp_sink_0 " + enc + ".rtp_src_0 ! " : std::string()) +
       "udpsink name=" + kRtpOut + " host=" + c.host + " port=" + std::to_string(c.port) +
       " sync=false async=false ";
  d += std::string(kRtpBin) + ".send_rtcp_src_0 ! " +
       (c.srtp_key ? enc + ".rtcp_sink_0 " + enc + ".rtcp_src_0 ! " : std::string()) +
       "udpsink name=" + kRtcpOut + " host=" + c.host + " port=" + std::to_string(c.port + 1) +
       " sync=false async=false ";
  // The station's RTCP (receiver reports, NACK, PLI) comes back to the socket RTCP leaves from:
  // RtpSender hands this udpsrc's socket to the RTCP udpsink. With a key it is SRTCP, and what
  // the key does not authenticate never reaches rtpbin (a forged NACK or PLI would make work).
  const std::string dec = kSrtcpDecoder;
  d += std::string("udpsrc name=") + kRtcpIn + " port=0 caps=application/x-" +
       (c.srtp_key ? "srtcp ! " + dec + ".rtcp_sink srtpdec name=" + dec + " " + dec + ".rtcp_src"
                   : std::string("rtcp")) +
       " ! " + kRtpBin + ".recv_rtcp_sink_0";
  return d;
}

std::string rtx_send_description(const RtpSendConfig& c) {
  std::string map = std::to_string(c.payload_type) + "=(uint)" + std::to_string(c.rtx_payload_type);
  if (c.fec_percentage > 0)  // a lost FEC packet is asked for too (the station cannot tell)
    map += "," + std::to_string(c.fec_payload_type) + "=(uint)" +
           std::to_string(c.rtx_fec_payload_type);
  return std::string("rtprtxsend name=") + send_elements::kRtxSend +
         " payload-type-map=\"application/x-rtp-pt-map," + map +
         "\" max-size-time=" + std::to_string(c.rtx_history_ms) + " max-size-packets=0";
}

GstElement* make_fec_encoder(const RtpSendConfig& c) {
  GstElement* e = gst_element_factory_make("rtpulpfecenc", send_elements::kFecEncoder);
  if (e == nullptr) return nullptr;
  g_object_set(e, "pt", static_cast<guint>(c.fec_payload_type), "percentage",
               static_cast<guint>(c.fec_percentage), "multipacket", TRUE, nullptr);
  return e;  // floating: rtpbin adds it to itself
}

}  // namespace hd::remote
