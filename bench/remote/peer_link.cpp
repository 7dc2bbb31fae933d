// PeerLink: the plain GStreamer link the fair benchmark measures ours against.
#include "bench/remote/peer_link.h"

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/rtp/gstrtpbuffer.h>

#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gstreamer_init.h"
#include "remote/sender/h264_encoder.h"

namespace hd::bench {
namespace {

// The RTP time of an RTP buffer, or of a list's first.
bool rtp_time_of(GstBuffer* buffer, uint32_t& rtp_time) {
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp)) return false;
  rtp_time = gst_rtp_buffer_get_timestamp(&rtp);
  gst_rtp_buffer_unmap(&rtp);
  return true;
}

// x264enc moves its output into a segment 1000 h on (room for negative DTS): the payloaded
// buffer's running time is the PTS push() gave (appsrc's segment starts at 0).
uint64_t running_time(GstPad* pad, GstClockTime pts) {
  GstEvent* e = gst_pad_get_sticky_event(pad, GST_EVENT_SEGMENT, 0);
  if (e == nullptr) return pts;
  const GstSegment* segment = nullptr;
  gst_event_parse_segment(e, &segment);
  const GstClockTime t = gst_segment_to_running_time(segment, GST_FORMAT_TIME, pts);
  gst_event_unref(e);
  return t;
}

GstBuffer* first_buffer(GstPadProbeInfo* info) {
  if (GST_PAD_PROBE_INFO_TYPE(info) & GST_PAD_PROBE_TYPE_BUFFER_LIST) {
    GstBufferList* list = GST_PAD_PROBE_INFO_BUFFER_LIST(info);
    return gst_buffer_list_length(list) > 0 ? gst_buffer_list_get(list, 0) : nullptr;
  }
  return GST_PAD_PROBE_INFO_BUFFER(info);
}

void add_probe(GstElement* pipeline, const char* element, const char* pad,
               GstPadProbeCallback callback, gpointer self) {
  GstElement* e = gst_bin_get_by_name(GST_BIN(pipeline), element);
  GstPad* p = gst_element_get_static_pad(e, pad);
  gst_pad_add_probe(
      p, static_cast<GstPadProbeType>(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
      callback, self, nullptr);
  gst_object_unref(p);
  gst_object_unref(e);
}

}  // namespace

PeerLink::PeerLink(const PeerLinkConfig& c) : period_ns_(1'000'000'000ull / c.rate_hz) {
  drivers::ensure_gstreamer();
  const std::string encoder = remote::kSoftwareH264Encoder;
  const std::string port = std::to_string(c.port);
  const int key_int = std::max(1, c.rate_hz / 2);  // RtpSendConfig's 0.5 s
  const int vbv_ms = (1000 + c.rate_hz - 1) / c.rate_hz;
  description_ =
      "appsrc name=src is-live=true format=time do-timestamp=false max-buffers=2 "
      "leaky-type=downstream caps=video/x-raw,format=RGBA,width=" +
      std::to_string(c.width_px) + ",height=" + std::to_string(c.height_px) +
      ",framerate=" + std::to_string(c.rate_hz) +
      "/1 ! videoconvert ! video/x-raw,format=" + remote::h264_encoder_input_format(encoder) +
      " ! " + remote::h264_encoder_description(encoder, c.bitrate_kbps, key_int, vbv_ms, false) +
      " ! rtph264pay name=pay config-interval=-1 pt=96 mtu=1200 ! udpsink host=127.0.0.1 port=" +
      port + " sync=false async=false udpsrc name=net address=127.0.0.1 port=" + port +
      " caps=application/x-rtp,media=video,clock-rate=90000,encoding-name=H264,payload=96 ! "
      "rtpjitterbuffer latency=20 ! rtph264depay name=depay ! avdec_h264 name=dec max-threads=1 ! "
      "videoconvert ! video/x-raw,format=RGBA ! appsink name=sink sync=false max-buffers=1 "
      "drop=true";
  GError* error = nullptr;
  pipeline_ = gst_parse_launch(description_.c_str(), &error);
  if (error != nullptr) {
    const std::string why = error->message;
    g_error_free(error);
    if (pipeline_ != nullptr) gst_object_unref(pipeline_);
    throw std::runtime_error("peer link: " + why);
  }
  source_ = gst_bin_get_by_name(GST_BIN(pipeline_), "src");
  add_probe(
      pipeline_, "pay", "sink",
      [](GstPad* pad, GstPadProbeInfo* info, gpointer self) {
        if (GstBuffer* b = first_buffer(info))
          static_cast<PeerLink*>(self)->on_encoded(running_time(pad, GST_BUFFER_PTS(b)));
        return GST_PAD_PROBE_OK;
      },
      this);
  add_probe(
      pipeline_, "net", "src",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        if (GstBuffer* b = first_buffer(info)) static_cast<PeerLink*>(self)->on_received(b);
        return GST_PAD_PROBE_OK;
      },
      this);
  add_probe(
      pipeline_, "dec", "src",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        if (GstBuffer* b = first_buffer(info)) static_cast<PeerLink*>(self)->on_decoded(b);
        return GST_PAD_PROBE_OK;
      },
      this);
  add_probe(
      pipeline_, "pay", "src",
      [](GstPad* pad, GstPadProbeInfo* info, gpointer self) {
        if (GstBuffer* b = first_buffer(info))
          static_cast<PeerLink*>(self)->on_payloaded(b, running_time(pad, GST_BUFFER_PTS(b)));
        return GST_PAD_PROBE_OK;
      },
      this);
  add_probe(
      pipeline_, "depay", "sink",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        if (GstBuffer* b = first_buffer(info))
          static_cast<PeerLink*>(self)->on_depayloader_input(b);
        return GST_PAD_PROBE_OK;
      },
      this);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline_), "sink");
  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = [](GstAppSink* s, gpointer self) {
    static_cast<PeerLink*>(self)->on_sample(GST_ELEMENT(s));
    return GST_FLOW_OK;
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(sink), &callbacks, this, nullptr);
  gst_object_unref(sink);
  if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("peer link: the pipeline does not start: " + description_);
}

PeerLink::~PeerLink() {
  gst_element_set_state(pipeline_, GST_STATE_NULL);
  gst_object_unref(source_);
  gst_object_unref(pipeline_);
}

void PeerLink::push(const drivers::Frame& f, int64_t capture_ns) {
  const std::size_t bytes = std::size_t(f.stride_bytes) * f.height;
  GstBuffer* b =
      gst_buffer_new_wrapped_full(GST_MEMORY_FLAG_READONLY, const_cast<uint8_t*>(f.data.data()),
                                  bytes, 0, bytes, nullptr, nullptr);
  const uint64_t pts = pushed_++ * period_ns_;
  GST_BUFFER_PTS(b) = pts;
  GST_BUFFER_DURATION(b) = period_ns_;
  {
    std::lock_guard lock(mutex_);
    capture_by_pts_.put(pts, capture_ns);
  }
  gst_app_src_push_buffer(GST_APP_SRC(source_), b);
}

void PeerLink::on_encoded(uint64_t pushed_pts) {
  const int64_t now = drivers::monotonic_now_ns();
  std::lock_guard lock(mutex_);
  encoded_by_pts_.put(pushed_pts, now);
}

void PeerLink::on_payloaded(GstBuffer* rtp, uint64_t pushed_pts) {
  uint32_t rtp_time = 0;
  if (!rtp_time_of(rtp, rtp_time)) return;
  std::lock_guard lock(mutex_);
  PeerFrameTiming t;
  if (!capture_by_pts_.get(pushed_pts, t.capture_ns)) return;
  encoded_by_pts_.get(pushed_pts, t.encoded_ns);
  PeerFrameTiming known;
  if (!timing_by_rtp_.get(rtp_time, known)) timing_by_rtp_.put(rtp_time, t);
}

void PeerLink::on_received(GstBuffer* rtp) {
  uint32_t rtp_time = 0;
  if (!rtp_time_of(rtp, rtp_time)) return;
  const int64_t now = drivers::monotonic_now_ns();
  std::lock_guard lock(mutex_);
  PeerFrameTiming t;
  if (timing_by_rtp_.get(rtp_time, t)) {
    t.received_ns = now;  // each packet's arrival: the last one stays
    timing_by_rtp_.set(rtp_time, t);
  }
}

void PeerLink::on_depayloader_input(GstBuffer* rtp) {
  uint32_t rtp_time = 0;
  if (!rtp_time_of(rtp, rtp_time)) return;
  std::lock_guard lock(mutex_);
  rtp_by_pts_.put(GST_BUFFER_PTS(rtp), rtp_time);
}

void PeerLink::on_decoded(GstBuffer* frame) {
  const int64_t now = drivers::monotonic_now_ns();
  std::lock_guard lock(mutex_);
  uint32_t rtp_time = 0;
  if (rtp_by_pts_.get(GST_BUFFER_PTS(frame), rtp_time)) decoded_by_rtp_.set(rtp_time, now);
}

void PeerLink::on_sample(GstElement* sink) {
  GstSample* sample = gst_app_sink_pull_sample(GST_APP_SINK(sink));
  if (sample == nullptr) return;
  const int64_t now = drivers::monotonic_now_ns();
  const GstBuffer* b = gst_sample_get_buffer(sample);
  std::lock_guard lock(mutex_);
  ++out_;
  uint32_t rtp_time = 0;
  PeerFrameTiming t;
  if (b != nullptr && rtp_by_pts_.get(GST_BUFFER_PTS(b), rtp_time) &&
      timing_by_rtp_.get(rtp_time, t)) {
    decoded_by_rtp_.get(rtp_time, t.decoded_ns);
    t.available_ns = now;
    timings_.push_back(t);
  }
  gst_sample_unref(sample);
}

std::vector<PeerFrameTiming> PeerLink::take_timings() {
  std::lock_guard lock(mutex_);
  std::vector<PeerFrameTiming> out;
  out.swap(timings_);
  return out;
}

uint64_t PeerLink::frames_out() const {
  std::lock_guard lock(mutex_);
  return out_;
}

}  // namespace hd::bench
