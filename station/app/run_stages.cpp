// RunStages: latency records and model snapshots into each source's StageDelays.
#include "station/app/run_stages.h"

#include <cmath>

namespace hd::station {
namespace {

double ms_since(int64_t from_ns, int64_t to_ns) {
  return from_ns != 0 && to_ns != 0 ? 1e-6 * double(to_ns - from_ns) : NAN;
}

}  // namespace

RunStages::RunStages(std::size_t cameras)
    : video_(cameras, StageDelays::video()), model_(StageDelays::model()) {}

void RunStages::after_frame(const render::LatencyRecord& r, int camera, const ModelSnapshot* model,
                            int64_t now_ns) {
  if (r.video_ns != 0 && camera >= 0 && static_cast<std::size_t>(camera) < video_.size()) {
    StageDelays& v = video_[static_cast<std::size_t>(camera)];
    v.stage(1).add(ms_since(r.video_ns, r.video_encoded_ns), now_ns);
    v.stage(2).add(ms_since(r.video_ns, r.video_sent_ns), now_ns);
    v.stage(3).add(ms_since(r.video_ns, r.video_received_ns), now_ns);
    v.stage(4).add(ms_since(r.video_ns, r.video_decoded_ns), now_ns);
    v.stage(5).add(ms_since(r.video_ns, r.predicted_display_ns), now_ns);
  }
  if (model == nullptr || model->update == 0) return;
  if (model->update != last_model_update_) {
    last_model_update_ = model->update;
    model_.stage(1).add(ms_since(model->capture_oldest_ns, model->reconstructed_ns), now_ns);
    model_.stage(2).add(ms_since(model->capture_oldest_ns, model->published_ns), now_ns);
  }
  model_.stage(3).add(ms_since(r.model_capture_ns, r.predicted_display_ns), now_ns);
}

std::string RunStages::hud_text(int camera, const std::vector<std::string>& camera_names,
                                int64_t now_ns) const {
  std::string text;
  if (camera >= 0 && static_cast<std::size_t>(camera) < video_.size()) {
    const std::string v = video_[static_cast<std::size_t>(camera)].hud_text(now_ns);
    if (!v.empty())
      text += (static_cast<std::size_t>(camera) < camera_names.size()
                   ? camera_names[static_cast<std::size_t>(camera)]
                   : std::string("video")) +
              ": " + v;
  }
  const std::string m = model_.hud_text(now_ns);
  if (!m.empty()) text += (text.empty() ? "" : " | ") + std::string("model: ") + m;
  return text;
}

std::vector<StageFigure> stage_figures(const StageDelays& d) {
  std::vector<StageFigure> figures;
  for (std::size_t i = 1; i < d.names().size(); ++i)
    if (d.stage(i).count() > 0) figures.push_back({d.names()[i], d.stage(i).p50_run()});
  return figures;
}

}  // namespace hd::station
