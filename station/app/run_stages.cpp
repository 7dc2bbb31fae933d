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

void RunStages::sample_graph(int camera, int64_t now_ns) {
  const bool video = camera >= 0 && static_cast<std::size_t>(camera) < video_.size();
  const int source = video ? camera : -1;
  const StageDelays& d = video ? video_[static_cast<std::size_t>(camera)] : model_;
  if (source != graph_source_) {
    graph_source_ = source;
    history_.assign(d.names().size() - 1, {});
  }
  for (std::size_t i = 0; i < history_.size(); ++i) {
    std::vector<double>& h = history_[i];
    if (h.size() == kGraphSamples) h.erase(h.begin());
    h.push_back(d.stage(i + 1).p50_last_second(now_ns));
  }
}

render::HudGraph RunStages::graph(const std::vector<std::string>& camera_names) const {
  render::HudGraph g;
  if (graph_source_ < -1) return g;
  const bool video = graph_source_ >= 0;
  const StageDelays& d = video ? video_[static_cast<std::size_t>(graph_source_)] : model_;
  const std::size_t cam = static_cast<std::size_t>(std::max(0, graph_source_));
  g.title = (video ? (cam < camera_names.size() ? camera_names[cam] : std::string("video"))
                   : std::string("model")) +
            ": ms since capture, p50 of each second";
  g.names.assign(d.short_names().begin() + 1, d.short_names().end());
  g.series = history_;
  // Stages never stamped (a local camera has no link) stay out of the graph and its legend.
  for (std::size_t i = g.series.size(); i-- > 0;) {
    bool any = false;
    for (double v : g.series[i]) any = any || std::isfinite(v);
    if (!any) {
      g.series.erase(g.series.begin() + static_cast<std::ptrdiff_t>(i));
      g.names.erase(g.names.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
  return g;
}

std::vector<StageFigure> stage_figures(const StageDelays& d) {
  std::vector<StageFigure> figures;
  for (std::size_t i = 1; i < d.names().size(); ++i)
    if (d.stage(i).count() > 0) figures.push_back({d.names()[i], d.stage(i).p50_run()});
  return figures;
}

}  // namespace hd::station
