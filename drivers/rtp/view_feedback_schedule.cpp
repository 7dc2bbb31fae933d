// ViewFeedbackSchedule: the HDBW message's cadence and content.
#include "drivers/rtp/view_feedback_schedule.h"

#include <span>

namespace hd::drivers {

ViewFeedbackSchedule::ViewFeedbackSchedule(std::optional<ViewFeedbackKey> key) : key_(key) {}

void ViewFeedbackSchedule::set_target(const std::string& host, int port) {
  std::lock_guard lock(mutex_);
  host_ = host;
  port_ = port;
  sent_ns_ = 0;
}

bool ViewFeedbackSchedule::due(int64_t now_ns) const {
  const int need = need_.load(std::memory_order_relaxed);
  std::lock_guard lock(mutex_);
  if (need < 0 || port_ == 0) return false;
  return need != sent_need_ || sent_ns_ == 0 || now_ns - sent_ns_ >= kRepeatNs;
}

ViewFeedbackSchedule::Message ViewFeedbackSchedule::take(int64_t now_ns) {
  const int need = need_.load(std::memory_order_relaxed);
  std::lock_guard lock(mutex_);
  Message m;
  m.host = host_;
  m.port = port_;
  const ViewFeedback message{0, need == 1, ++sequence_};
  if (key_) {
    write_view_feedback(message, *key_,
                        std::span<uint8_t, kAuthenticatedViewFeedbackSize>(m.bytes));
    m.size = kAuthenticatedViewFeedbackSize;
  } else {
    write_view_feedback(message,
                        std::span<uint8_t, kViewFeedbackSize>(m.bytes.data(), kViewFeedbackSize));
    m.size = kViewFeedbackSize;
  }
  sent_ns_ = now_ns;
  sent_need_ = need;
  return m;
}

}  // namespace hd::drivers
