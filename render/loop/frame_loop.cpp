#include "render/loop/frame_loop.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hd::render {

FrameLoop::FrameLoop(FrameLoopConfig config, LoopClock& clock)
    : config_(config), clock_(clock), display_period_ns_(0), period_ns_(0) {
  if (!std::isfinite(config.rate_hz) || config.rate_hz <= 0.0 || config.rate_hz > 1000.0)
    throw std::invalid_argument("frame loop: rate_hz must be in (0, 1000], got " +
                                std::to_string(config.rate_hz));
  if (config.scanout_latency_ns < 0)
    throw std::invalid_argument("frame loop: scanout_latency_ns must be >= 0");
  display_period_ns_ = static_cast<int64_t>(std::llround(1e9 / config.rate_hz));
  period_ns_ = display_period_ns_;
}

void FrameLoop::set_divisor(int divisor) {
  if (divisor < 1)
    throw std::invalid_argument("frame loop: divisor must be >= 1, got " + std::to_string(divisor));
  divisor_ = divisor;
  period_ns_ = display_period_ns_ * divisor;
}

FrameTiming FrameLoop::tick(FrameWork& work) {
  if (!started_) {
    next_start_ns_ = clock_.now_ns();
    prev_start_ns_ = next_start_ns_;
    started_ = true;
  }
  if (config_.pace) clock_.sleep_until_ns(next_start_ns_);
  FrameTiming t;
  t.frame = frames_;
  t.start_ns = next_start_ns_;
  t.deadline_ns = t.start_ns + period_ns_;
  t.display_ns = t.deadline_ns + config_.scanout_latency_ns;
  t.dt_s = static_cast<double>(t.start_ns - prev_start_ns_) * 1e-9;
  prev_start_ns_ = t.start_ns;

  const int64_t work_start_ns = clock_.now_ns();
  work.tick(t);

  const int64_t end_ns = clock_.now_ns();
  last_work_ns_ = end_ns - work_start_ns;
  last_lateness_ns_ = end_ns - t.deadline_ns;
  if (end_ns > t.deadline_ns) ++missed_;
  ++frames_;
  next_start_ns_ = t.deadline_ns;
  if (config_.pace && end_ns > next_start_ns_) {
    // The next slot started while this frame was still drawing: join the display's first slot
    // after `end` (the display's period: a slower rate still starts on its vsync grid).
    const int64_t behind = (end_ns - next_start_ns_) / display_period_ns_ + 1;
    next_start_ns_ += behind * display_period_ns_;
    skipped_ += static_cast<uint64_t>(behind);
  } else if (!config_.pace && end_ns > next_start_ns_) {
    next_start_ns_ = end_ns;
  }
  return t;
}

void FrameLoop::run(uint64_t frames, FrameWork& work) {
  for (uint64_t i = 0; i < frames; ++i) tick(work);
}

}  // namespace hd::render
