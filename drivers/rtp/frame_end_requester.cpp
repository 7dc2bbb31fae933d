#include "drivers/rtp/frame_end_requester.h"

#include <algorithm>

#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {

std::shared_ptr<FrameEndRequester> FrameEndRequester::create(FrameEndWatch::Settings s) {
  std::shared_ptr<FrameEndRequester> r(new FrameEndRequester(s));
  r->settings_ = s;
  r->clock_ = gst_system_clock_obtain();  // CLOCK_MONOTONIC, as monotonic_now_ns()
  return r;
}

FrameEndRequester::~FrameEndRequester() {
  shutdown();
  if (clock_ != nullptr) gst_object_unref(clock_);
}

void FrameEndRequester::set_jitter_buffer(GstElement* jitter_buffer) {
  std::lock_guard lock(m_);
  if (jitter_buffer_ != nullptr) gst_object_unref(jitter_buffer_);
  jitter_buffer_ = jitter_buffer != nullptr ? GST_ELEMENT(gst_object_ref(jitter_buffer)) : nullptr;
  watch_ = FrameEndWatch(settings_);
  asked_count_ = 0;
}

void FrameEndRequester::on_packet(uint32_t ssrc, uint16_t sequence, bool marker,
                                  int64_t arrival_ns) {
  std::lock_guard lock(m_);
  if (!live_) return;
  if (ssrc != 0) ssrc_ = ssrc;
  watch_.on_packet(sequence, marker, arrival_ns);
  arm();
}

void FrameEndRequester::arm() {
  const int64_t due = watch_.due_ns();
  // A pending timer fires first and re-arms for a later due time: never more than one.
  if (due == 0 || timer_ != nullptr || clock_ == nullptr) return;
  timer_ = gst_clock_new_single_shot_id(clock_, static_cast<GstClockTime>(due));
  timer_due_ns_ = due;
  // The clock's thread holds a reference to this until the callback ran or was unscheduled.
  auto* self = new std::weak_ptr<FrameEndRequester>(weak_from_this());
  gst_clock_id_wait_async(
      timer_,
      [](GstClock*, GstClockTime, GstClockID, gpointer data) -> gboolean {
        if (const auto r = static_cast<std::weak_ptr<FrameEndRequester>*>(data)->lock())
          r->on_timer();
        return TRUE;
      },
      self, [](gpointer data) { delete static_cast<std::weak_ptr<FrameEndRequester>*>(data); });
}

void FrameEndRequester::on_timer() {
  GstElement* jb = nullptr;
  GstStructure* request = nullptr;
  {
    std::lock_guard lock(m_);
    if (timer_ != nullptr) {
      gst_clock_id_unref(timer_);
      timer_ = nullptr;
    }
    if (!live_) return;
    const std::optional<uint16_t> seq = watch_.on_due(monotonic_now_ns());
    if (seq && jitter_buffer_ != nullptr) {
      ++requests_;
      asked_[asked_next_] = *seq;
      asked_next_ = (asked_next_ + 1) % asked_.size();
      asked_count_ = std::min(asked_count_ + 1, asked_.size());
      jb = GST_ELEMENT(gst_object_ref(jitter_buffer_));
      // The fields rtpsession reads (gstrtpsession.c): the NACK must leave within deadline -
      // round trip to be of use.
      request = gst_structure_new(
          "GstRTPRetransmissionRequest", "seqnum", G_TYPE_UINT, guint{*seq}, "ssrc", G_TYPE_UINT,
          guint{ssrc_}, "deadline", G_TYPE_UINT, static_cast<guint>(deadline_ms_), "avg-rtt",
          G_TYPE_UINT, static_cast<guint>(round_trip_ms_), "retry", G_TYPE_UINT,
          static_cast<guint>(0), "delay", G_TYPE_UINT, static_cast<guint>(0), nullptr);
    }
    arm();
  }
  if (jb == nullptr) return;
  if (GstPad* sink = gst_element_get_static_pad(jb, "sink")) {
    gst_pad_push_event(sink, gst_event_new_custom(GST_EVENT_CUSTOM_UPSTREAM, request));
    gst_object_unref(sink);
  } else {
    gst_structure_free(request);
  }
  gst_object_unref(jb);
}

bool FrameEndRequester::take_repair(uint16_t sequence) {
  std::lock_guard lock(m_);
  for (std::size_t i = 0; i < asked_count_; ++i)
    if (asked_[i] == sequence) return true;
  return false;
}

void FrameEndRequester::set_deadline(int latency_ms, int round_trip_ms) {
  std::lock_guard lock(m_);
  deadline_ms_ = std::max(1, latency_ms);
  round_trip_ms_ = std::max(0, round_trip_ms);
}

void FrameEndRequester::set_wait(int64_t wait_ns) {
  std::lock_guard lock(m_);
  settings_.wait_ns = wait_ns;
  watch_.set_wait(wait_ns);
}

void FrameEndRequester::shutdown() {
  std::lock_guard lock(m_);
  live_ = false;
  if (timer_ != nullptr) {
    gst_clock_id_unschedule(timer_);
    gst_clock_id_unref(timer_);
    timer_ = nullptr;
  }
  if (jitter_buffer_ != nullptr) {
    gst_object_unref(jitter_buffer_);
    jitter_buffer_ = nullptr;
  }
}

uint64_t FrameEndRequester::requests() const {
  std::lock_guard lock(m_);
  return requests_;
}

}  // namespace hd::drivers
