#include "station/model/model_updater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hd::station {
namespace {

// Copies what an update changes into a slot made from the same initial model: the a-priori
// meshes' vertex positions and texels (equal sizes, nothing reallocated) and the reconstructed
// meshes whole (their vectors keep their capacity, so a slot grows only to the largest mesh).
void copy_model(const render::SyntheticScene& src, render::SyntheticScene& dst,
                std::size_t prior_meshes) {
  for (std::size_t m = 0; m < src.meshes.size() && m < dst.meshes.size(); ++m) {
    const render::TexturedMesh& s = src.meshes[m];
    render::TexturedMesh& d = dst.meshes[m];
    if (m >= prior_meshes) {
      d.positions_m = s.positions_m;
      d.uvs = s.uvs;
      d.triangles = s.triangles;
      d.texture.width = s.texture.width;
      d.texture.height = s.texture.height;
      d.texture.stride_bytes = s.texture.stride_bytes;
      d.texture.data = s.texture.data;
      continue;
    }
    if (d.positions_m.size() == s.positions_m.size())
      std::copy(s.positions_m.begin(), s.positions_m.end(), d.positions_m.begin());
    if (d.texture.data.size() == s.texture.data.size())
      std::copy(s.texture.data.begin(), s.texture.data.end(), d.texture.data.begin());
  }
  dst.revision = src.revision;
}

// The a-priori model followed by one placeholder mesh per stereo pair: as many vertices as the
// pair's mesh can ever have, no triangles, no texture (invalid: no compositor draws it), so a
// rasteriser that drew the initial model never needs to grow for a reconstruction.
render::SyntheticScene with_pair_meshes(
    const render::SyntheticScene& initial,
    const std::vector<std::unique_ptr<PairReconstruction>>& pairs) {
  render::SyntheticScene s = initial;
  for (const auto& p : pairs) {
    render::TexturedMesh m;
    m.positions_m.assign(p->max_vertices(), Eigen::Vector3f::Zero());
    s.meshes.push_back(std::move(m));
  }
  return s;
}

std::vector<std::unique_ptr<PairReconstruction>> make_pairs(
    const std::vector<ModelStereoPair>& config, const std::vector<ModelCamera>& cameras,
    const render::SyntheticScene& prior) {
  std::vector<std::unique_ptr<PairReconstruction>> pairs;
  for (const ModelStereoPair& p : config) {
    if (p.left >= cameras.size() || p.right >= cameras.size() || p.left == p.right)
      throw std::invalid_argument("model updater: stereo pair " + p.name +
                                  " names a camera that is not there (" + std::to_string(p.left) +
                                  ", " + std::to_string(p.right) + " of " +
                                  std::to_string(cameras.size()) + ")");
    const ModelCamera& l = cameras[p.left];
    const ModelCamera& r = cameras[p.right];
    pairs.push_back(
        std::make_unique<PairReconstruction>(p, l.p_c, l.T_world_cam, r.p_c, r.T_world_cam, prior));
  }
  return pairs;
}

ModelSnapshot initial_snapshot(const render::SyntheticScene& initial, std::size_t prior_meshes) {
  ModelSnapshot s;
  s.scene = initial;
  s.prior_meshes = prior_meshes;
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
      pairs_(make_pairs(config_.stereo_pairs, cameras_, initial)),
      prior_meshes_(initial.meshes.size()),
      working_(with_pair_meshes(initial, pairs_)),
      extractor_(config_.extractor),
      models_(initial_snapshot(working_, initial.meshes.size())),
      revision_(initial.revision) {
  if (!std::isfinite(config_.refresh_period_s) || config_.refresh_period_s <= 0)
    throw std::invalid_argument("model updater: refresh period must be positive seconds, got " +
                                std::to_string(config_.refresh_period_s));
  if (!std::isfinite(config_.delay_s) || config_.delay_s < 0)
    throw std::invalid_argument("model updater: delay must be >= 0 seconds, got " +
                                std::to_string(config_.delay_s));
  period_ns_ = static_cast<int64_t>(std::llround(config_.refresh_period_s * 1e9));
  delay_ns_ = static_cast<int64_t>(std::llround(config_.delay_s * 1e9));
  if (!std::isfinite(config_.pair_sync_timeout_s) || config_.pair_sync_timeout_s < 0)
    throw std::invalid_argument("model updater: pair sync timeout must be >= 0 seconds");
  // Occluders for the extractor (two per pair), after everything published: copy_model stops at
  // the slots' mesh count, so they never reach the station.
  working_.meshes.resize(prior_meshes_ + 3 * pairs_.size());
  views_.reserve(cameras_.size());
  extractor_.prepare(initial);  // the a-priori meshes; the reconstructed ones only occlude
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
  s.reconstructions = reconstructions_.load();
  s.reconstructions_refused = refused_.load();
  s.last_reconstruct_ns = last_reconstruct_ns_.load();
  s.max_reconstruct_ns = max_reconstruct_ns_.load();
  s.last_reconstructed_vertices = last_recon_vertices_.load();
  return s;
}

void ModelUpdater::sync_pairs(const std::atomic<bool>* running) {
  const int64_t deadline =
      clock_.now_ns() + static_cast<int64_t>(std::llround(config_.pair_sync_timeout_s * 1e9));
  constexpr int64_t kPollNs = 2'000'000;
  for (const auto& pr : pairs_) {
    const ModelStereoPair& p = pr->pair();
    if (attempts_ % static_cast<uint64_t>(p.every_updates) != 0) continue;
    drivers::Mailbox<drivers::Frame>* a = cameras_[p.left].frames;
    drivers::Mailbox<drivers::Frame>* b = cameras_[p.right].frames;
    if (a == nullptr || b == nullptr) continue;
    for (;;) {
      const int64_t ta = a->latest().host_timestamp_ns, tb = b->latest().host_timestamp_ns;
      if (ta == 0 || tb == 0) break;  // a camera without a frame: the pair is refused
      if (std::llabs(ta - tb) <= p.reconstruction.max_pair_skew_ns) break;
      const int64_t now = clock_.now_ns();
      if (now >= deadline || (running && !running->load(std::memory_order_acquire))) break;
      // The older camera's next frame is (nearly) the other one's exposure.
      if (!(ta < tb ? a : b)->fetch()) clock_.sleep_until_ns(now + kPollNs);
    }
  }
}

bool ModelUpdater::take_frames(const std::atomic<bool>* running) {
  views_.clear();  // keeps capacity: no allocation
  capture_oldest_ns_ = std::numeric_limits<int64_t>::max();
  capture_newest_ns_ = std::numeric_limits<int64_t>::min();
  for (const ModelCamera& cam : cameras_)
    if (cam.frames != nullptr)
      cam.frames->fetch();  // the newest model frame; the previous one when nothing new came
  if (!pairs_.empty()) sync_pairs(running);
  // Views are taken after the last fetch: a view points into its mailbox's read slot.
  for (const ModelCamera& cam : cameras_) {
    if (cam.frames == nullptr) continue;
    const drivers::Frame& f = cam.frames->latest();
    if (f.host_timestamp_ns == 0 || f.data.empty()) continue;  // never published
    // A frame that brought its calibration (a network camera's stream) is textured with it.
    if (f.calibration.present)
      views_.push_back({&f, f.calibration.p_c, f.calibration.T_world_cam});
    else if (cam.p_c.valid())
      views_.push_back({&f, cam.p_c, cam.T_world_cam});
    else
      continue;
    capture_oldest_ns_ = std::min(capture_oldest_ns_, f.host_timestamp_ns);
    capture_newest_ns_ = std::max(capture_newest_ns_, f.host_timestamp_ns);
  }
  taken_ns_ = clock_.now_ns();
  return !views_.empty();
}

bool ModelUpdater::update_once() {
  return update(nullptr);
}

void ModelUpdater::reconstruct_pairs() {
  const int64_t t0 = clock_.now_ns();
  uint64_t vertices = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    PairReconstruction& pr = *pairs_[k];
    const ModelStereoPair& p = pr.pair();
    if (attempts_ % static_cast<uint64_t>(p.every_updates) == 0) {
      static const drivers::Frame kMissing{};
      const drivers::Frame& l =
          cameras_[p.left].frames ? cameras_[p.left].frames->latest() : kMissing;
      const drivers::Frame& r =
          cameras_[p.right].frames ? cameras_[p.right].frames->latest() : kMissing;
      if (pr.update(l, r)) {
        working_.meshes[prior_meshes_ + k] = pr.mesh();
        reconstructions_.fetch_add(1, std::memory_order_relaxed);
      } else {
        refused_.fetch_add(1, std::memory_order_relaxed);
      }
    }
    // What the model shows of this pair is as old as the frames it was measured from.
    if (pr.capture_ns() > 0) {
      capture_oldest_ns_ = std::min(capture_oldest_ns_, pr.capture_ns());
      capture_newest_ns_ = std::max(capture_newest_ns_, pr.capture_ns());
    }
    vertices += working_.meshes[prior_meshes_ + k].positions_m.size();
    // The pair's surface pushed back along its left camera's rays: the hidden depth of what it
    // saw, so the extractor's occlusion test covers the objects' unseen backs.
    const render::TexturedMesh& seen = working_.meshes[prior_meshes_ + k];
    const Eigen::Vector3f c = cameras_[p.left].T_world_cam.t.cast<float>();
    for (int j = 0; j < 2; ++j) {
      render::TexturedMesh& occ = working_.meshes[prior_meshes_ + pairs_.size() + 2 * k + j];
      const float depth = static_cast<float>(p.occluder_depth_m) * (j == 0 ? 0.5f : 1.0f);
      occ.positions_m = seen.positions_m;
      for (Eigen::Vector3f& X : occ.positions_m) X += depth * (X - c).normalized();
      occ.uvs = seen.uvs;
      occ.triangles = seen.triangles;
      if (occ.texture.empty()) occ.texture.allocate(1, 1);
    }
  }
  reconstructed_ns_ = clock_.now_ns();
  reconstruct_ns_ = reconstructed_ns_ - t0;
  last_reconstruct_ns_.store(reconstruct_ns_, std::memory_order_relaxed);
  if (reconstruct_ns_ > max_reconstruct_ns_.load(std::memory_order_relaxed))
    max_reconstruct_ns_.store(reconstruct_ns_, std::memory_order_relaxed);
  last_recon_vertices_.store(vertices, std::memory_order_relaxed);
}

bool ModelUpdater::update(const std::atomic<bool>* running) {
  if (!take(running)) return false;
  if (delay_ns_ > 0) sleep_until(clock_, taken_ns_ + delay_ns_, running);
  if (running && !running->load(std::memory_order_acquire)) return false;  // stopped meanwhile
  finish();
  return true;
}

bool ModelUpdater::take(const std::atomic<bool>* running) {
  if (take_frames(running)) return true;
  without_frames_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool ModelUpdater::take_update() {
  return take(nullptr);
}

void ModelUpdater::finish_update() {
  finish();
}

void ModelUpdater::finish() {
  reconstruct_ns_ = reconstructed_ns_ = 0;
  if (!pairs_.empty()) reconstruct_pairs();
  ++attempts_;
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
}

void ModelUpdater::publish() {
  ModelSnapshot& slot = models_.write_slot();
  copy_model(working_, slot.scene, prior_meshes_);
  slot.prior_meshes = prior_meshes_;
  slot.reconstruct_ns = reconstruct_ns_;
  slot.reconstructed_ns = reconstructed_ns_;
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
