#pragma once
// The delayed synthetic model: textures re-extracted from camera frames at a low rate.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <thread>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/mailbox.h"
#include "render/loop/loop_clock.h"
#include "station/model/model_snapshot.h"
#include "station/model/pair_reconstruction.h"
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
/// Only the simulator can provide one, from its ground truth, and only when a scene asks for it
/// (`model.moved_objects: ground-truth`, for comparisons); a station's model otherwise learns of
/// moved objects from its stereo pairs.
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
  /// Camera pairs reconstructed at each update (indices into the cameras): their meshes of what
  /// the a-priori model does not hold follow the a-priori meshes in every snapshot.
  std::vector<ModelStereoPair> stereo_pairs{};
  /// How long an update waits for a pair's two newest frames to be of one exposure (the older
  /// camera's mailbox is polled) before the pair is refused as unsynchronised.
  double pair_sync_timeout_s = 0.1;
};

/// Measured by the updater's thread (read from any thread).
struct ModelUpdaterStats {
  uint64_t updates = 0;                 ///< snapshots published
  uint64_t updates_without_frames = 0;  ///< periods in which no camera had a frame (not published)
  uint64_t skipped_periods = 0;         ///< periods that passed while an update ran
  int64_t last_extract_ns = 0;          ///< duration of the newest extraction
  int64_t max_extract_ns = 0;
  uint64_t last_texels_updated = 0;
  uint64_t reconstructions = 0;          ///< pair reconstructions that rebuilt a mesh
  uint64_t reconstructions_refused = 0;  ///< pairs refused (missing, unsynchronised, not newer)
  int64_t last_reconstruct_ns = 0;       ///< all pairs of the newest update
  int64_t max_reconstruct_ns = 0;
  uint64_t last_reconstructed_vertices = 0;  ///< all pairs' meshes in the newest snapshot
};

/// Background thread: every refresh period it takes the newest model frame of each camera (a
/// camera with no frame yet is left out; the two cameras of a stereo pair are waited for until
/// their frames are of one exposure), waits `delay_s`, reconstructs the pairs that are due
/// (PairReconstruction: their meshes of what the a-priori model lacks replace the previous
/// ones), moves the objects to the frames' capture time when a ground-truth callback is given,
/// projects the frames onto its working copy of the a-priori meshes (TextureExtractor; the
/// reconstructed meshes occlude), bumps `revision` and publishes a ModelSnapshot into
/// `models()`. A snapshot's capture_oldest_ns is the oldest frame in it, reconstructed meshes
/// included, and its publish time comes after the reconstruction: the model's age includes it.
/// The mailbox's three slots are copies of the initial model made in the constructor;
/// publishing copies the a-priori part into a slot without reallocating (the reconstructed
/// meshes may grow a slot, on this thread), so the station's fetch is lock- and allocation-free.
/// Until the first update, `models().latest()` is the initial (a-priori) model with capture
/// times 0 and empty reconstructed meshes. Slots not yet published show that model too.
class ModelUpdater {
 public:
  /// `clock` (now + absolute sleeps) must outlive the updater; tests pass a fake one.
  /// Throws std::invalid_argument for a non-positive or non-finite period or a negative delay,
  /// a pair naming a camera that is not there; recon::RigError for a pair that cannot be one.
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

  /// A run on the scene's clock drives the two halves of an update itself, with the model's
  /// delay between them on its own clock (`hybrid-station score`): take_update() takes the
  /// cameras' newest model frames now (false, counted, when none had one: nothing to finish);
  /// finish_update() reconstructs, textures and publishes them. update_once() is take, wait,
  /// finish. Not while the thread runs.
  bool take_update();
  void finish_update();

  /// The station's mailbox (single consumer).
  drivers::Mailbox<ModelSnapshot>& models() { return models_; }
  ModelUpdaterStats stats() const;
  const ModelUpdaterConfig& config() const { return config_; }

 private:
  void run();
  bool update(const std::atomic<bool>* running);  ///< running: cut a delay wait short on stop
  bool take(const std::atomic<bool>* running);    ///< take_frames, counted when there were none
  void finish();                                  ///< reconstruct, move, extract, publish
  bool take_frames(const std::atomic<bool>* running);
  void sync_pairs(const std::atomic<bool>* running);
  void reconstruct_pairs();
  void publish();

  ModelUpdaterConfig config_;
  render::LoopClock& clock_;
  std::vector<ModelCamera> cameras_;
  std::vector<std::unique_ptr<PairReconstruction>> pairs_;
  std::size_t prior_meshes_ = 0;  ///< meshes [0, prior_meshes_) are the a-priori model
  uint64_t attempts_ = 0;         ///< updates with frames (a pair is due every n-th)
  int64_t reconstruct_ns_ = 0, reconstructed_ns_ = 0;
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
  std::atomic<uint64_t> reconstructions_{0};
  std::atomic<uint64_t> refused_{0};
  std::atomic<int64_t> last_reconstruct_ns_{0};
  std::atomic<int64_t> max_reconstruct_ns_{0};
  std::atomic<uint64_t> last_recon_vertices_{0};
};

}  // namespace hd::station
