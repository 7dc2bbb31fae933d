#include "station/app/score_outputs.h"

#include <algorithm>
#include <cmath>

#include "station/app/frames_csv.h"
#include "station/app/output_file.h"
#include "station/app/report_text.h"
#include "station/app/station_config.h"

namespace hd::station {
namespace {

std::string number(double v, const char* f = "%.4f") {
  return std::isfinite(v) ? fmt(f, v) : std::string();
}

}  // namespace

void write_score_csv(const std::vector<ScoreRow>& rows, const std::string& path) {
  std::string s =
      "frame,t_s,eye,variant,camera,m,w_video,psnr_db,ssim,gmsd,psnr_video_db,psnr_blend_db,"
      "psnr_synthetic_db,video_fraction,psnr_pure_video_db,psnr_pure_synthetic_db,old_fraction\n";
  for (const ScoreRow& r : rows)
    s += std::to_string(r.frame) + "," + fmt("%.6f", r.t_s) + "," + std::to_string(r.eye) + "," +
         variant_name(r.variant) + "," + r.camera + "," + number(r.m, "%.3f") + "," +
         fmt("%.4f", r.w_video) + "," + number(r.whole.psnr_db) + "," +
         number(r.whole.ssim, "%.5f") + "," + number(r.whole.gmsd, "%.5f") + "," +
         number(r.psnr_video_db) + "," + number(r.psnr_blend_db) + "," +
         number(r.psnr_synthetic_db) + "," + fmt("%.4f", r.video_fraction) + "," +
         number(r.psnr_pure_video_db) + "," + number(r.psnr_pure_synthetic_db) + "," +
         fmt("%.4f", r.old_fraction) + "\n";
  write_text_atomically(s, path);
}

void write_tuning_csv(const std::vector<TuningResult>& results, const std::string& path) {
  std::string s = "mode,m_t,eps,psnr_mean_db,psnr_p5_db,video_share\n";
  for (const TuningResult& r : results)
    s += std::string(transition_mode_name(r.candidate.mode)) + "," + fmt("%g", r.candidate.m_t) +
         "," + fmt("%g", r.candidate.eps) + "," + fmt("%.4f", r.psnr_mean_db) + "," +
         fmt("%.4f", r.p5_db) + "," + fmt("%.4f", r.video_share) + "\n";
  write_text_atomically(s, path);
}

nlohmann::json distribution(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return {{"count", 0}};
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {
    return v[static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1)))];
  };
  double sum = 0.0;
  for (double x : v) sum += x;
  return {{"count", v.size()},
          {"mean", sum / static_cast<double>(v.size())},
          {"p5", at(0.05)},
          {"p50", at(0.5)},
          {"p95", at(0.95)}};
}

nlohmann::json scores_of(const std::vector<const ScoreRow*>& rows) {
  std::vector<double> psnr, ssim, gmsd, pv, ps, vf, old;
  for (const ScoreRow* r : rows) {
    psnr.push_back(r->whole.psnr_db);
    ssim.push_back(r->whole.ssim);
    gmsd.push_back(r->whole.gmsd);
    pv.push_back(r->psnr_video_db);
    ps.push_back(r->psnr_synthetic_db);
    vf.push_back(r->video_fraction);
    old.push_back(r->old_fraction);
  }
  return {{"eye_frames", rows.size()},          {"psnr_db", distribution(psnr)},
          {"ssim", distribution(ssim)},         {"gmsd", distribution(gmsd)},
          {"psnr_video_db", distribution(pv)},  {"psnr_synthetic_db", distribution(ps)},
          {"video_fraction", distribution(vf)}, {"old_fraction", distribution(old)}};
}

}  // namespace hd::station
