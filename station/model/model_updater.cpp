#include "station/model/model_updater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hd::station {
namespace {

// Copies what an update changes (vertex positions and texels) into a slot made from the same
// initial model: equal sizes, so nothing is reallocated.
void copy_model(const render::SyntheticScene& src, render::SyntheticScene& dst) {
  for (std::size_t m = 0; m < src.meshes.size() && m < dst.meshes.size(); ++m) {
    const render::TexturedMesh& s = src.meshes[m];
    render::TexturedMesh& d = dst.meshes[m];
    if (d.positions_m.size() == s.positions_m.size())
      std::copy(s.positions_m.begin(), s.positions_m.end(), d.positions_m.begin());
    if (d.texture.data.size() == s.texture.data.size())
      std::copy(s.texture.data.begin(), s.texture.data.end(), d.texture.data.begin());
  }
  dst.revision = src.revision;
}

ModelSnapshot initial_snapshot(const render::SyntheticScene& initial) {
  ModelSnapshot s;
  s.scene = initial;
  return s;
}

// Sleeps in short steps so stop() is prompt even during a long staleness delay.
void sleep_until(render::LoopClock& clock, int64_t t_ns, const std::atomic<bool>* running) {
  constexpr int64_t kStepNs = 20'000'000;
  for (;;) {
    const int64_t now = clock.now_ns();
    if (now >= t_ns) return;
    if (running && !running->load(std::memory_order_acquire)) return;
    clock.sleep_until_ns(running ? std::min(t_ns, now + kStepNs) : t_ns);
  }
}

}  // namespace

ModelUpdater::ModelUpdater(const render::SyntheticScene& initial,
                           std::span<const ModelCamera> cameras, ModelUpdaterConfig config,
                           render::LoopClock& clock)
    : config_(std::move(config)),
      clock_(clock),
      cameras_(cameras.begin(), cameras.end()),
      working_(initial),
      extractor_(config_.extractor),
      models_(initial_snapshot(initial)),
      revision_(initial.revision) {
  if (!std::isfinite(config_.refresh_period_s) || config_.refresh_period_s <= 0)
    throw std::invalid_argument("model updater: refresh period must be positive seconds, got " +
                                std::to_string(config_.refresh_period_s));
  if (!std::isfinite(config_.delay_s) || config_.delay_s < 0)
    throw std::invalid_argument("model updater: delay must be >= 0 seconds, got " +
                                std::to_string(config_.delay_s));
  period_ns_ = static_cast<int64_t>(std::llround(config_.refresh_period_s * 1e9));
  delay_ns_ = static_cast<int64_t>(std::llround(config_.delay_s * 1e9));
  views_.reserve(cameras_.size());
  extractor_.prepare(working_);
}

ModelUpdater::~ModelUpdater() {
  stop();
}

void ModelUpdater::start() {
  if (running_.load()) return;
  running_.store(true);
  thread_ = std::thread([this] { run(); });
}

void ModelUpdater::stop() {
  running_.store(false);
  if (thread_.joinable()) thread_.join();
}

ModelUpdaterStats ModelUpdater::stats() const {
  ModelUpdaterStats s;
  s.updates = updates_.load();
  s.updates_without_frames = without_frames_.load();
  s.skipped_periods = skipped_.load();
  s.last_extract_ns = last_extract_ns_.load();
  s.max_extract_ns = max_extract_ns_.load();
  s.last_texels_updated = last_texels_.load();
  return s;
}

bool ModelUpdater::take_frames() {
  views_.clear();  // keeps capacity: no allocation
  capture_oldest_ns_ = std::numeric_limits<int64_t>::max();
  capture_newest_ns_ = std::numeric_limits<int64_t>::min();
  for (const ModelCamera& cam : cameras_) {
    if (cam.frames == nullptr) continue;
    cam.frames->fetch();  // the newest model frame; the previous one when nothing new came
    const drivers::Frame& f = cam.frames->latest();
    if (f.host_timestamp_ns == 0 || f.data.empty()) continue;  // never published
    views_.push_back({&f, cam.p_c, cam.T_world_cam});
    capture_oldest_ns_ = std::min(capture_oldest_ns_, f.host_timestamp_ns);
    capture_newest_ns_ = std::max(capture_newest_ns_, f.host_timestamp_ns);
  }
  taken_ns_ = clock_.now_ns();
  return !views_.empty();
}

bool ModelUpdater::update_once() {
  return update(nullptr);
}

bool ModelUpdater::update(const std::atomic<bool>* running) {
  if (!take_frames()) {
    without_frames_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (delay_ns_ > 0) sleep_until(clock_, taken_ns_ + delay_ns_, running);
  if (running && !running->load(std::memory_order_acquire)) return false;  // stopped meanwhile
  if (config_.move_objects) config_.move_objects(working_, capture_oldest_ns_);
  const int64_t t0 = clock_.now_ns();
  extractor_.extract(working_, views_);
  const int64_t extract_ns = clock_.now_ns() - t0;
  working_.revision = ++revision_;
  publish();
  last_extract_ns_.store(extract_ns, std::memory_order_relaxed);
  if (extract_ns > max_extract_ns_.load(std::memory_order_relaxed))
    max_extract_ns_.store(extract_ns, std::memory_order_relaxed);
  last_texels_.store(extractor_.last_stats().texels_updated, std::memory_order_relaxed);
  return true;
}

void ModelUpdater::publish() {
  ModelSnapshot& slot = models_.write_slot();
  copy_model(working_, slot.scene);
  slot.capture_oldest_ns = capture_oldest_ns_;
  slot.capture_newest_ns = capture_newest_ns_;
  slot.taken_ns = taken_ns_;
  slot.published_ns = clock_.now_ns();
  slot.update = updates_.load(std::memory_order_relaxed) + 1;
  models_.publish();
  updates_.fetch_add(1, std::memory_order_relaxed);
}

void ModelUpdater::run() {
  int64_t next_ns = clock_.now_ns();
  while (running_.load(std::memory_order_acquire)) {
    sleep_until(clock_, next_ns, &running_);
    if (!running_.load(std::memory_order_acquire)) break;
    update(&running_);
    if (!running_.load(std::memory_order_acquire)) break;
    // Next slot on the t0 + k * period grid; slots that passed during this update are skipped.
    next_ns += period_ns_;
    const int64_t now = clock_.now_ns();
    if (now > next_ns) {
      const int64_t missed = (now - next_ns) / period_ns_ + 1;
      skipped_.fetch_add(static_cast<uint64_t>(missed), std::memory_order_relaxed);
      next_ns += missed * period_ns_;
    }
  }
}

}  // namespace hd::station
