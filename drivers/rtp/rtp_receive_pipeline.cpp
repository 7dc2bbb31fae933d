#include "drivers/rtp/rtp_receive_pipeline.h"

#include <algorithm>
#include <cstdio>

#include "drivers/rtp/srtp_elements.h"

namespace hd::drivers {
namespace {

// udpsrc's kernel receive buffer (it forces one above net.core.rmem_max where it may); 0 keeps
// the system's default.
std::string buffer_size(int bytes) {
  return bytes > 0 ? " buffer-size=" + std::to_string(bytes) : std::string();
}

}  // namespace

int initial_latency_ms(const RtpReceiveConfig& c) {
  if (!c.jitter_buffer_auto) return c.jitter_buffer_latency_ms;
  return std::clamp(c.jitter_buffer_start_ms, c.jitter_buffer_latency_ms,
                    std::max(c.jitter_buffer_latency_ms, c.jitter_buffer_max_ms));
}

std::string receive_pipeline_description(const RtpReceiveConfig& c) {
  using namespace rtp_elements;
  const std::string host = c.listen.host, port = std::to_string(c.listen.port),
                    rtcp_port = std::to_string(c.listen.port + 1);
  std::string d;
  d += std::string("rtpbin name=") + kRtpBin + " latency=" + std::to_string(initial_latency_ms(c)) +
       " do-retransmission=" + (c.retransmission ? "true" : "false") +
       // A packet given up on is a GstRTPPacketLost event: the camera marks the stream damaged
       // and, unless it heals by intra refresh, asks for a key frame at once (PLI).
       " do-lost=true" +
       // AVPF (RFC 4585): NACK and PLI leave as early feedback, not at the next regular report.
       " rtp-profile=avpf ";
  // No drop-on-latency: it drops the oldest packet whenever the RTP times held span the
  // latency, i.e. at a latency of a frame period or more (which the measured budget often is)
  // the packets of a frame still inside its deadline. The jitter buffer holds no more than its
  // latency anyway: it never waits for the decoder, which runs behind the queue.
  d += "drop-on-latency=false ";
  d += std::string("udpsrc name=") + kRtpSource + " address=" + host + " port=" + port +
       " reuse=false" + buffer_size(c.receive_buffer_bytes) + " caps=\"application/x-" +
       (c.srtp_key ? "srtp" : "rtp") + ",media=video,clock-rate=90000,encoding-name=H264,payload=" +
       std::to_string(c.payload_type) +
       // The sender supports RTCP feedback: PLI on loss (the depayloader's key-frame request) and
       // NACK.
       ",rtcp-fb-nack-pli=(boolean)true,rtcp-fb-nack=(boolean)true\" ";
  if (c.srtp_key)
    d += std::string("! ") + kSrtpDecoder + ".rtp_sink srtpdec name=" + kSrtpDecoder + " " +
         (c.netsim() ? std::string(kSrtpDecoder) + ".rtp_src " : std::string());
  if (c.netsim()) {
    char p[32];
    std::snprintf(p, sizeof p, "%.6f", c.netsim_drop_probability);
    d += std::string("! netsim name=") + kNetsim + " drop-probability=" + p +
         " min-delay=" + std::to_string(c.netsim_min_delay_ms) +
         " max-delay=" + std::to_string(c.netsim_max_delay_ms) +
         // netsim delays a packet only with delay-probability (default 0: none at all).
         " delay-probability=" + (c.netsim_max_delay_ms > 0 ? "1.0" : "0.0") +
         // Jitter as a queue's: its delay varies, its order does not (netsim_reorder: it may).
         " allow-reordering=" + (c.netsim_reorder ? "true" : "false") +
         " delay-distribution=uniform ";
  }
  // The media chain's last element is linked to rtpbin.recv_rtp_sink_0 by the camera once it
  // can answer request-aux-receiver (receive_media_link).
  d += std::string("udpsrc name=") + kRtcpSource + " address=" + host + " port=" + rtcp_port +
       " reuse=false" + buffer_size(c.rtcp_receive_buffer_bytes) +
       (c.srtp_key ? std::string(" caps=application/x-srtcp ! ") + kSrtpDecoder + ".rtcp_sink " +
                         kSrtpDecoder + ".rtcp_src ! "
                   : std::string(" caps=application/x-rtcp ! ")) +
       kRtpBin + ".recv_rtcp_sink_0 ";
  d += std::string(kRtpBin) + ".send_rtcp_src_0 ! " +
       (c.srtp_key ? std::string(kSrtpEncoder) + ".rtcp_sink_0 srtpenc name=" + kSrtpEncoder + " " +
                         kSrtpEncoderCiphers + " " + kSrtpEncoder + ".rtcp_src_0 ! "
                   : std::string()) +
       "multiudpsink name=" + kRtcpSink + " sync=false async=false ";
  // The jitter buffer's own thread pushes into a queue, and the queue's thread depayloads,
  // decodes: a decoder that waits for a CPU must not hold the jitter buffer, which
  // with drop-on-latency then drops the packets that piled up beyond its latency (measured: up
  // to 124 in 2 s with the CPUs busy, each costing the frames up to the next key frame).
  d += std::string(kRtpBin) + ". ! queue name=" + kDecodeQueue +
       " max-size-buffers=0 max-size-bytes=0 max-size-time=" +
       std::to_string(int64_t{c.decode_queue_ms} * 1'000'000) + " ! " + depayloader_description() +
       " ! " + decoder_description() + " ! appsink name=" + kAppSink +
       " sync=false max-buffers=1 drop=true";
  return d;
}

std::string depayloader_description() {
  // Neither waits for nor asks for a key frame after a loss: RtpCamera judges each access unit
  // (h264_heal_watch.h) and asks itself, also for a stream that heals by intra refresh.
  return std::string("rtph264depay name=") + rtp_elements::kDepayloader;
}

std::string decoder_description() {
  // No videoconvert: RtpCamera converts the decoded frame into its mailbox slot, where an RGBA
  // buffer from videoconvert had to be copied (0.5 ms a 1280x720 frame, hybrid-bench-network).
  return std::string("avdec_h264 name=") + rtp_elements::kDecoder + " max-threads=1";
}

MediaLink receive_media_link(const RtpReceiveConfig& c) {
  using namespace rtp_elements;
  if (c.netsim()) return {kNetsim, "src"};
  if (c.srtp_key) return {kSrtpDecoder, "rtp_src"};
  return {kRtpSource, "src"};
}

std::string rtx_receive_description(const RtpReceiveConfig& c) {
  std::string map = std::to_string(c.payload_type) + "=(uint)" + std::to_string(c.rtx_payload_type);
  if (c.fec)
    map += "," + std::to_string(c.fec_payload_type) + "=(uint)" +
           std::to_string(c.rtx_fec_payload_type);
  return std::string("rtprtxreceive name=") + rtp_elements::kRtxReceive +
         " payload-type-map=\"application/x-rtp-pt-map," + map + "\"";  // original → RTX, as sent
}

}  // namespace hd::drivers
