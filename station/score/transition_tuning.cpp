#include "station/score/transition_tuning.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hd::station {

TransitionTuner::TransitionTuner(std::vector<TuningCandidate> candidates,
                                 core::TransitionParams base)
    : candidates_(std::move(candidates)) {
  for (const TuningCandidate& c : candidates_) {
    core::TransitionParams p = base;
    p.mode = c.mode;
    p.m_t = c.m_t;
    p.eps = c.eps;
    transitions_.emplace_back(p);
  }
  psnr_.resize(candidates_.size());
  frames_with_video_.assign(candidates_.size(), 0);
}

std::vector<TuningCandidate> TransitionTuner::default_grid() {
  // m in the scenes runs from a few px (the head at the camera) to several hundred; the grid is
  // finer where the paper's 40 px sits. m_t = 0 with the abrupt mode never shows video: the
  // synthetic view alone is a candidate too.
  const double m_ts[] = {0, 5, 10, 15, 20, 25, 30, 40, 50, 60, 80, 100, 150, 200, 300};
  const double epss[] = {0, 2.5, 5, 10, 20, 40};
  std::vector<TuningCandidate> grid;
  for (double m_t : m_ts) grid.push_back({core::TransitionMode::kAbrupt, m_t, 0.0});
  for (core::TransitionMode mode :
       {core::TransitionMode::kGlobalBlend, core::TransitionMode::kPerPixel})
    for (double m_t : m_ts)
      for (double eps : epss) grid.push_back({mode, m_t, eps});
  return grid;
}

void TransitionTuner::add_frame(double m, double dt_s, double w_cap,
                                std::span<const BlendErrorModel* const> eyes) {
  begin_frame(m, dt_s, w_cap);
  std::vector<std::vector<double>> scores(eyes.size());
  for (std::size_t e = 0; e < eyes.size(); ++e) score_eye(*eyes[e], scores[e]);
  end_frame(scores, !eyes.empty() && eyes[0]->has_video());
}

void TransitionTuner::begin_frame(double m, double dt_s, double w_cap) {
  pictures_.clear();
  picture_of_.resize(candidates_.size());
  w_.resize(candidates_.size());
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    const double w = transitions_[i].update(m, dt_s, w_cap).w_video;
    // Pure video and pure model look the same in every mode.
    const bool per_pixel =
        candidates_[i].mode == core::TransitionMode::kPerPixel && w > 0.0 && w < 1.0;
    auto it = std::find_if(pictures_.begin(), pictures_.end(),
                           [&](const Picture& p) { return p.per_pixel == per_pixel && p.w == w; });
    if (it == pictures_.end()) it = pictures_.insert(pictures_.end(), {per_pixel, w});
    picture_of_[i] = static_cast<std::size_t>(it - pictures_.begin());
    w_[i] = w;
  }
}

void TransitionTuner::score_eye(const BlendErrorModel& eye, std::vector<double>& psnr) const {
  psnr.clear();
  for (const Picture& p : pictures_)
    psnr.push_back(eye.psnr_db(
        p.per_pixel ? core::TransitionMode::kPerPixel : core::TransitionMode::kGlobalBlend, p.w));
}

void TransitionTuner::end_frame(std::span<const std::vector<double>> eyes, bool has_video) {
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    for (const std::vector<double>& e : eyes) psnr_[i].push_back(e.at(picture_of_[i]));
    if (w_[i] > 0.0 && has_video) ++frames_with_video_[i];
  }
  ++frames_;
}

std::vector<TuningResult> TransitionTuner::results() const {
  std::vector<TuningResult> out;
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    TuningResult r;
    r.candidate = candidates_[i];
    std::vector<double> v = psnr_[i];
    r.eye_frames = v.size();
    if (!v.empty()) {
      double sum = 0.0;
      for (double x : v) sum += x;
      r.psnr_mean_db = sum / static_cast<double>(v.size());
      std::sort(v.begin(), v.end());
      r.p5_db = v[static_cast<std::size_t>(std::floor(0.05 * static_cast<double>(v.size() - 1)))];
    }
    r.video_share = frames_ ? static_cast<double>(frames_with_video_[i]) / frames_ : 0.0;
    out.push_back(r);
  }
  return out;
}

TuningResult TransitionTuner::best(core::TransitionMode mode) const {
  const std::vector<TuningResult> all = results();
  const TuningResult* best = nullptr;
  for (const TuningResult& r : all)
    if (r.candidate.mode == mode && (!best || r.psnr_mean_db > best->psnr_mean_db)) best = &r;
  if (!best) throw std::logic_error("transition tuning: no candidate of that mode");
  return *best;
}

}  // namespace hd::station
