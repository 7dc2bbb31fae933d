#pragma once
// The m_t and eps that would have shown the operator the best picture: every candidate transition
// replayed over the run's own frames, each frame scored from its BlendErrorModel.
//
// The station's m does not depend on the transition (the camera is chosen by m alone), so a run
// records, per frame, everything a transition sees: m, dt and the video's age cap. Each candidate
// is a core::Transition (the station's own class, the same hysteresis and time constant) fed the
// same sequence; its w_video in each frame gives the picture's error through the frame's model.
// One run thus scores a whole grid. What it does not replay: a frame in which the run itself had
// no camera left on screen (no camera usable and its video faded out) scores every candidate as
// the model, though a slower candidate could still have shown the fading video there.
//
// The score of a candidate is the mean PSNR over the run's eye-frames of the picture it would
// have shown, scored without marking and HUD like the run.

#include <cstddef>
#include <span>
#include <vector>

#include "core/transition.h"
#include "station/score/blend_error_model.h"

namespace hd::station {

struct TuningCandidate {
  core::TransitionMode mode = core::TransitionMode::kPerPixel;
  double m_t = 40.0;
  double eps = 10.0;  ///< unused by kAbrupt (it switches with the station's hysteresis)
};

struct TuningResult {
  TuningCandidate candidate;
  double psnr_mean_db = 0.0;
  double p5_db = 0.0;        ///< the bad eye-frames
  double video_share = 0.0;  ///< share of frames with any video on screen (video or hybrid)
  std::size_t eye_frames = 0;
};

class TransitionTuner {
 public:
  /// `base`: the station's transition parameters (hysteresis, time constant); each candidate
  /// replaces mode, m_t and eps.
  TransitionTuner(std::vector<TuningCandidate> candidates, core::TransitionParams base);

  /// m_t from 0 to 300 px and eps from 0 to 40 px for both blend modes, m_t alone for abrupt.
  static std::vector<TuningCandidate> default_grid();

  /// One displayed frame as the station decided it (FrameRow: m, w_cap; the tick's dt) and
  /// each eye's error model: begin_frame, score_eye per eye, end_frame.
  void add_frame(double m, double dt_s, double w_cap, std::span<const BlendErrorModel* const> eyes);

  /// The same in three steps, so that the eyes can be scored on their own threads: advances
  /// every candidate's transition by one frame and collects the distinct pictures (mode, w)
  /// they show (most candidates show pure video or pure model, so there are few).
  void begin_frame(double m, double dt_s, double w_cap);
  /// This frame's distinct pictures scored for one eye, PSNR in dB, into `psnr` (const: safe
  /// from several threads at once).
  void score_eye(const BlendErrorModel& eye, std::vector<double>& psnr) const;
  /// Records each eye's scores (from score_eye) for every candidate; `has_video`: the frame had
  /// video to show.
  void end_frame(std::span<const std::vector<double>> eyes, bool has_video);

  /// Every candidate, in the order given.
  std::vector<TuningResult> results() const;
  /// The candidate with the highest mean PSNR among those of `mode` (candidates of that mode
  /// must exist; throws std::logic_error otherwise).
  TuningResult best(core::TransitionMode mode) const;
  /// Candidate i's PSNR per eye-frame, in the order added (to check a replay against the run).
  const std::vector<double>& trace(std::size_t i) const { return psnr_[i]; }

 private:
  std::vector<TuningCandidate> candidates_;
  std::vector<core::Transition> transitions_;
  std::vector<std::vector<double>> psnr_;
  std::vector<std::size_t> frames_with_video_;
  struct Picture {
    bool per_pixel;
    double w;
  };
  std::vector<Picture> pictures_;        ///< this frame's distinct pictures
  std::vector<std::size_t> picture_of_;  ///< per candidate: its index into pictures_
  std::vector<double> w_;                ///< per candidate: its w_video this frame
  std::size_t frames_ = 0;
};

}  // namespace hd::station
