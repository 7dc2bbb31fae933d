#pragma once
// What `hybrid-station score` writes besides its plots: score.csv (one row per frame and eye),
// tuning.csv (every candidate transition replayed) and score.json's distributions.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "station/app/score_row.h"
#include "station/score/transition_tuning.h"

namespace hd::station {

/// score.csv, written whole or not at all. A score with nothing to score is an empty field.
void write_score_csv(const std::vector<ScoreRow>& rows, const std::string& path);

/// tuning.csv: mode, m_t, eps and each candidate's mean and p5 PSNR and video share.
void write_tuning_csv(const std::vector<TuningResult>& results, const std::string& path);

/// Count, mean, p5, p50 and p95 of the finite values (p5: the bad frames of a "higher is
/// better" score); {"count": 0} when there are none.
nlohmann::json distribution(std::vector<double> v);

/// The rows' eye-frame count and the distribution of each score.
nlohmann::json scores_of(const std::vector<const ScoreRow*>& rows);

}  // namespace hd::station
