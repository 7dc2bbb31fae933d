#pragma once
// The delayed synthetic model: textures re-extracted from camera frames at a low rate.

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <thread>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/mailbox.h"
#include "render/loop/loop_clock.h"
#include "station/model/model_snapshot.h"
#include "station/model/texture_extractor.h"

namespace hd::station {

/// A camera the model is textured from: the mailbox of undistorted frames it takes
/// (CameraPipeline::model_frames(); the updater is its single consumer) and the pinhole those
/// frames match, at pose T_world_cam.
struct ModelCamera {
  drivers::Mailbox<drivers::Frame>* frames = nullptr;
  core::Pinhole p_c;  ///< the undistorted pinhole of the frames (distortion is ignored)
  core::Pose T_world_cam;
};

/// Moves the model's moving objects (vertex positions only: same counts, same textures) to
/// where they were at `capture_ns` (CLOCK_MONOTONIC, the oldest frame used in this update).
/// The simulator provides one; a real station passes none (its geometry is static).
using MoveModelObjects = std::function<void(render::SyntheticScene& model, int64_t capture_ns)>;

struct ModelUpdaterConfig {
  double refresh_period_s = 1.0;  ///< updates start at t0 + k * period (skipped when late)
  /// Extra wait between taking the frames and texturing/publishing (the paper's model delay, as
  /// a simulated effect; 0 for real devices, whose delay is the extraction itself). When
  /// delay_s + extraction exceeds the period, the slots that passed are skipped (counted): updates
  /// stay on the t0 + k * period grid.
  double delay_s = 0.0;
  MoveModelObjects move_objects{};
  TextureExtractorParams extractor{};
};

/// Measured by the updater's thread (read from any thread).
struct ModelUpdaterStats {
  uint64_t updates = 0;                 ///< snapshots published
  uint64_t updates_without_frames = 0;  ///< periods in which no camera had a frame (not published)
  uint64_t skipped_periods = 0;         ///< periods that passed while an update ran
  int64_t last_extract_ns = 0;          ///< duration of the newest extraction
  int64_t max_extract_ns = 0;
  uint64_t last_texels_updated = 0;
};

/// Background thread: every refresh period it takes the newest model frame of each camera (a
/// camera with no frame yet is left out), waits `delay_s`, moves the objects to the frames'
/// capture time, projects the frames onto its working copy of the model (TextureExtractor),
/// bumps `revision` and publishes a ModelSnapshot into `models()`. The mailbox's three slots are
/// copies of the initial model made in the constructor; publishing copies into a slot without
/// reallocating (the model's shape never changes), so the station's fetch is lock- and
/// allocation-free. Until the first update, `models().latest()` is the initial (a-priori) model
/// with capture times 0. Slots not yet published show that model too.
class ModelUpdater {
 public:
  /// `clock` (now + absolute sleeps) must outlive the updater; tests pass a fake one.
  /// Throws std::invalid_argument for a non-positive or non-finite period or a negative delay.
  ModelUpdater(const render::SyntheticScene& initial, std::span<const ModelCamera> cameras,
               ModelUpdaterConfig config, render::LoopClock& clock);
  ~ModelUpdater();  ///< stops
  ModelUpdater(const ModelUpdater&) = delete;
  ModelUpdater& operator=(const ModelUpdater&) = delete;

  void start();
  /// Joins the thread; an update in progress finishes first (a delay wait is cut short).
  void stop();

  /// Runs one update now on the calling thread (take frames, wait the delay on the clock,
  /// move, extract, publish). Returns false when no camera had a frame. For tests and for a
  /// station that wants the model textured before its first frame; not while the thread runs.
  bool update_once();

  /// The station's mailbox (single consumer).
  drivers::Mailbox<ModelSnapshot>& models() { return models_; }
  ModelUpdaterStats stats() const;
  const ModelUpdaterConfig& config() const { return config_; }

 private:
  void run();
  bool update(const std::atomic<bool>* running);  ///< running: cut a delay wait short on stop
  bool take_frames();
  void publish();

  ModelUpdaterConfig config_;
  render::LoopClock& clock_;
  std::vector<ModelCamera> cameras_;
  std::vector<ExtractionView> views_;  ///< the cameras that had a frame this update
  render::SyntheticScene working_;
  TextureExtractor extractor_;
  drivers::Mailbox<ModelSnapshot> models_;
  int64_t period_ns_ = 0;
  int64_t delay_ns_ = 0;
  int64_t capture_oldest_ns_ = 0;
  int64_t capture_newest_ns_ = 0;
  int64_t taken_ns_ = 0;
  uint64_t revision_ = 0;

  std::atomic<bool> running_{false};
  std::thread thread_;
  std::atomic<uint64_t> updates_{0};
  std::atomic<uint64_t> without_frames_{0};
  std::atomic<uint64_t> skipped_{0};
  std::atomic<int64_t> last_extract_ns_{0};
  std::atomic<int64_t> max_extract_ns_{0};
  std::atomic<uint64_t> last_texels_{0};
};

}  // namespace hd::station
