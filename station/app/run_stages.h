#pragma once
// The run's stage delays (StageDelays) fed between frames from what each frame showed: its
// latency record (the video's capture and link stages, as drivers::Frame::LinkStages carried
// them, and the predicted display time), the camera it chose, and the model snapshot it drew.

#include <cstdint>
#include <string>
#include <vector>

#include "render/latency/latency_record.h"
#include "render/overlay/hud_graph.h"
#include "station/app/run_summary.h"
#include "station/app/stage_delays.h"
#include "station/model/model_snapshot.h"

namespace hd::station {

class RunStages {
 public:
  explicit RunStages(std::size_t cameras);

  /// After each frame: its latency record, the camera it chose (-1 none) and the model snapshot
  /// it drew (null without an updater). Each stage is the time since the capture.
  void after_frame(const render::LatencyRecord& newest, int camera, const ModelSnapshot* model,
                   int64_t now_ns);

  /// The HUD's text for camera `camera` (the chosen one; -1 none) and the model; "" when neither
  /// has a stage in the last second.
  std::string hud_text(int camera, const std::vector<std::string>& camera_names,
                       int64_t now_ns) const;

  /// At each HUD update: the last second's p50 of each stage of camera `camera` (the chosen one;
  /// -1: the model's) into the graph's history, which starts again when the source changes.
  void sample_graph(int camera, int64_t now_ns);
  /// The HUD's graph: that source's stages, time since capture, over the last kGraphSamples
  /// updates.
  render::HudGraph graph(const std::vector<std::string>& camera_names) const;
  static constexpr std::size_t kGraphSamples = 40;  // 20 s at the HUD's 2 updates a second

  const StageDelays& video(std::size_t camera) const { return video_.at(camera); }
  const StageDelays& model() const { return model_; }

 private:
  std::vector<StageDelays> video_;
  StageDelays model_;
  uint64_t last_model_update_ = 0;
  int graph_source_ = -2;                     // -2 none yet, -1 the model, else a camera
  std::vector<std::vector<double>> history_;  // per stage after capture, oldest first
};

/// The run's p50 of each stage after capture that has a sample, for the summary.
std::vector<StageFigure> stage_figures(const StageDelays& d);

}  // namespace hd::station
