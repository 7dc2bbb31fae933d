#pragma once
// What a run did, printed at the end and written as DIR/summary.json (scripts read it, e.g. the
// soak's missed-deadline rate).

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "drivers/camera_link.h"
#include "render/latency/latency_recorder.h"
#include "station/app/camera_events.h"
#include "station/app/rate_holder.h"
#include "station/app/usability_log.h"

namespace hd::station {

// (At namespace scope, not nested: clang cannot default-construct a nested struct with member
// initializers inside std::optional before the enclosing class is complete.)
/// What each network camera received (its link's report, drivers/camera_link.h) and what the
/// station made of it.
struct NetworkCameraSummary : drivers::LinkReport {
  uint64_t need_changes = 0;  ///< how often the view's need of it changed
  /// Where its p_c / P_c came from at the end: "stream (revision N)", "file F", or "none
  /// (no calibration arrived)"; frames not shown for want of one.
  std::string calibration;
  uint64_t frames_uncalibrated = 0;
};
/// A stage's p50 time since capture over the run.
struct StageFigure {
  std::string stage;
  double p50_ms = 0.0;
};
/// One camera's run, in the station's camera order.
struct CameraSummary {
  std::string name;
  uint64_t frames_shown = 0;     ///< frames in which its frame was new
  uint64_t frames_rejected = 0;  ///< by the pipeline (wrong size / format)
  uint64_t frames_lost = 0;      ///< by the device: sequence gaps, overruns
  /// The stretches in which its video was withheld (too old, source not streaming).
  std::vector<UnusableInterval> unusable;
  std::optional<NetworkCameraSummary> network;  ///< a network camera's link
  /// Its stages (StageDelays::video()) as p50 ms since capture over the run; stages without a
  /// sample are left out.
  std::vector<StageFigure> stages;
};

struct RunSummary {
  std::string source;  ///< "scene <file>" or "config <file>"
  uint64_t frames = 0;
  double seconds = 0.0;     ///< wall time of the loop
  double rate_hz = 0.0;     ///< the display's
  std::string rate_policy;  ///< hold | fixed
  /// The rates the frames ran at (the display's, or a divisor of it), with their frames and the
  /// misses against each; missed_deadlines is their sum.
  std::vector<HeldRate> rates;
  uint64_t rate_changes = 0;
  uint64_t missed_deadlines = 0;
  uint64_t skipped_slots = 0;
  render::LatencyStats mtp_swap, mtp_display, video_age, model_age, render;
  uint64_t variant_frames[3] = {0, 0, 0};  ///< video, hybrid, synthetic
  uint64_t guidance_frames = 0;
  uint64_t camera_switches = 0;
  std::vector<CameraEventRecord> camera_events;  ///< format lost / restored, in the order seen
  using NetworkCamera = NetworkCameraSummary;
  using Camera = CameraSummary;
  std::vector<Camera> cameras;
  std::string cameras_from;  ///< --cameras-from ("": the scene's cameras simulated in-process)
  std::string scene_epoch;   ///< --scene-epoch as given ("": scene t = 0 at this run's start)
  double first_frame_scene_s = 0.0;  ///< scene time of the first frame (with a scene epoch)
  /// Frames in which some camera's video was withheld for its age or its source's state.
  uint64_t frames_stale_blocked = 0;
  uint64_t pose_accepted = 0, pose_rejected = 0;
  uint64_t recentres = 0, tracker_resets = 0;
  uint64_t model_updates = 0;
  std::vector<StageFigure> model_stages;  ///< StageDelays::model(), as CameraSummary::stages
  /// Stereo pairs reconstructed into the model / refused (a camera without a frame, frames not
  /// of one exposure, not newer).
  uint64_t reconstructions = 0, reconstructions_refused = 0;
  uint64_t allocations_after_warmup = 0;
  uint64_t warmup_frames = 0;
  uint64_t log_rows = 0, log_rows_dropped = 0;
  uint64_t video_frames = 0, png_frames = 0, recorder_dropped = 0;
  std::string recorder_error;
  std::vector<std::string> outputs;

  double missed_rate() const {
    return frames ? static_cast<double>(missed_deadlines) / static_cast<double>(frames) : 0.0;
  }
};

void print_summary(const RunSummary& s, std::FILE* out);
/// JSON, written atomically; throws std::runtime_error naming the file on failure.
void write_summary_json(const RunSummary& s, const std::string& path);

}  // namespace hd::station
