// RtpCalibrationCache: the streamed calibrations by revision.
#include "drivers/rtp/rtp_calibration_cache.h"

namespace hd::drivers {

void RtpCalibrationCache::add(const StreamCalibration& c) {
  received_.fetch_add(1, std::memory_order_relaxed);
  std::lock_guard lock(mutex_);
  if (!held_[0] || held_[0]->revision != c.revision) {
    for (std::size_t i = kSize - 1; i > 0; --i) held_[i] = held_[i - 1];
  }
  held_[0] = c;
}

void RtpCalibrationCache::refuse(CalibrationError e) {
  if (e == CalibrationError::kNone || e == CalibrationError::kCount) return;
  refused_[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
}

FrameCalibration RtpCalibrationCache::lookup(uint32_t revision) const {
  std::lock_guard lock(mutex_);
  for (const std::optional<StreamCalibration>& c : held_)
    if (c && c->revision == revision) return {true, c->revision, c->p_c, c->T_world_cam};
  return {};
}

bool RtpCalibrationCache::fits(const FrameCalibration& c, int width, int height) {
  if (!c.present || (c.p_c.width == width && c.p_c.height == height)) return true;
  size_mismatch_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void RtpCalibrationCache::count_published(bool calibrated) {
  if (calibrated) frames_with_calibration_.fetch_add(1, std::memory_order_relaxed);
}

std::optional<StreamCalibration> RtpCalibrationCache::newest() const {
  std::lock_guard lock(mutex_);
  return held_[0];
}

RtpCalibrationCache::Counts RtpCalibrationCache::counts() const {
  Counts n;
  for (std::size_t i = 0; i < n.refused.size(); ++i) {
    n.refused[i] = refused_[i].load(std::memory_order_relaxed);
    n.refused_total += n.refused[i];
  }
  n.received = received_.load(std::memory_order_relaxed);
  n.frames_with_calibration = frames_with_calibration_.load(std::memory_order_relaxed);
  n.size_mismatch = size_mismatch_.load(std::memory_order_relaxed);
  return n;
}

}  // namespace hd::drivers
