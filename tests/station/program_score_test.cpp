// hybrid-station score: the same scene gives the same score.csv whatever the thread count (the
// scene's clock, not the machine's), and its PSNR agrees with one recomputed from the saved
// pictures by a plain formula and by OpenCV's cv::PSNR.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/text_file.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using hd::station::testing::slurp;
using hd::station::testing::split_csv_line;

constexpr int kFrames = 24;
constexpr int kSaveEvery = 8;

fs::path suite_dir() {
  return fs::temp_directory_path() / ("station_score_test_" + std::to_string(::getpid()));
}

// Runs the built hybrid-station score from the source tree; the exit code.
int score(const std::string& args, const fs::path& log) {
  const std::string cmd = "cd '" + std::string(hd::test::source_dir()) + "' && '" +
                          std::string(hd::test::station_bin()) + "' score " + args + " > '" +
                          log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::vector<std::string>> rows_of(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream s(csv);
  std::string line;
  while (std::getline(s, line)) rows.push_back(split_csv_line(line));
  return rows;
}

// The default scene scored once with one thread, and once with two threads saving every 8th
// frame's pictures; each test runs (once per process: ctest runs each test alone) what it reads.
class ScoreRun : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(suite_dir(), ec);
  }
  // A 1 ms age bound: every video frame (30 ms camera delay) is older than it.
  static fs::path one() { return run_once("one", "--threads 1 --age-bound-ms 1"); }
  static fs::path two() {
    return run_once("two",
                    "--threads 2 --age-bound-ms 1 --save-frames " + std::to_string(kSaveEvery));
  }

 private:
  static fs::path run_once(const std::string& name, const std::string& extra) {
    const fs::path out = suite_dir() / name;
    if (!fs::exists(out / "score.json")) {
      fs::create_directories(suite_dir());
      const int rc = score(
          "--frames " + std::to_string(kFrames) + " " + extra + " --out '" + out.string() + "'",
          suite_dir() / (name + ".log"));
      EXPECT_EQ(rc, 0) << slurp(suite_dir() / (name + ".log"));
    }
    return out;
  }
};

TEST_F(ScoreRun, TheSameSceneGivesTheSameScoresWhateverTheThreadCount) {
  const std::string a = slurp(one() / "score.csv");
  const std::string b = slurp(two() / "score.csv");
  EXPECT_EQ(a, b);
  const auto rows = rows_of(a);
  ASSERT_EQ(rows.size(), 1u + 2u * kFrames);  // header, then both eyes of every frame
  EXPECT_EQ(rows[0], split_csv_line("frame,t_s,eye,variant,camera,m,w_video,psnr_db,ssim,gmsd,"
                                    "psnr_video_db,psnr_blend_db,psnr_synthetic_db,video_fraction,"
                                    "psnr_pure_video_db,psnr_pure_synthetic_db,old_fraction"));
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), rows[0].size()) << "row " << i;
    EXPECT_EQ(std::stoi(rows[i][0]), static_cast<int>((i - 1) / 2));
    EXPECT_EQ(std::stoi(rows[i][2]), static_cast<int>((i - 1) % 2));
    const double psnr = std::stod(rows[i][7]), ssim = std::stod(rows[i][8]);
    EXPECT_GT(psnr, 15.0) << "row " << i;  // the station shows the scene, not noise
    EXPECT_LE(psnr, 100.0);
    EXPECT_GT(ssim, 0.5);
    EXPECT_LE(ssim, 1.0);
    // Pixels showing mostly video show a frame older than 1 ms; the share is a share.
    const double old = std::stod(rows[i][16]);
    EXPECT_GE(old, 0.0);
    EXPECT_LE(old, 1.0);
    if (rows[i][3] == "video") {
      EXPECT_GT(old, 0.3) << "row " << i;
    }
  }
}

TEST_F(ScoreRun, PsnrRecomputedFromTheSavedPicturesAgrees) {
  const auto rows = rows_of(slurp(two() / "score.csv"));
  int compared = 0;
  for (int frame = 0; frame < kFrames; frame += kSaveEvery)
    for (int eye = 0; eye < 2; ++eye) {
      char stem[64];
      std::snprintf(stem, sizeof stem, "%06d_eye%d", frame, eye);
      const fs::path dir = two() / "frames";
      const cv::Mat shown = cv::imread((dir / (std::string(stem) + "_shown.png")).string());
      const cv::Mat truth = cv::imread((dir / (std::string(stem) + "_truth.png")).string());
      ASSERT_FALSE(shown.empty()) << stem;
      ASSERT_EQ(shown.size(), truth.size());
      // A plain formula: mean squared difference over every colour value, then 10 log10.
      double sse = 0.0;
      for (int y = 0; y < shown.rows; ++y)
        for (int x = 0; x < shown.cols * 3; ++x) {
          const double d = double(shown.ptr<uint8_t>(y)[x]) - double(truth.ptr<uint8_t>(y)[x]);
          sse += d * d;
        }
      const double mse = sse / (3.0 * shown.rows * shown.cols);
      const double psnr = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 100.0;
      const auto& row = rows[static_cast<std::size_t>(1 + 2 * frame + eye)];
      EXPECT_NEAR(std::stod(row[7]), psnr, 0.01) << stem;
      // And another tool: OpenCV's cv::PSNR over the same two files (BGR, every value alike).
      EXPECT_NEAR(std::stod(row[7]), cv::PSNR(shown, truth), 0.01) << stem;
      ++compared;
    }
  EXPECT_EQ(compared, 6);
}

TEST_F(ScoreRun, TheSummaryHoldsTheSettingsTheScoresAndTheSpeed) {
  const nlohmann::json j = nlohmann::json::parse(slurp(one() / "score.json"));
  EXPECT_EQ(j["settings"]["frames"].get<int>(), kFrames);
  EXPECT_EQ(j["settings"]["eyes"].get<int>(), 2);
  EXPECT_EQ(j["overall"]["eye_frames"].get<int>(), 2 * kFrames);
  // The mean PSNR lies within the rows' range.
  const auto rows = rows_of(slurp(one() / "score.csv"));
  double lo = 1e9, hi = -1e9;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    lo = std::min(lo, std::stod(rows[i][7]));
    hi = std::max(hi, std::stod(rows[i][7]));
  }
  const double mean = j["overall"]["psnr_db"]["mean"].get<double>();
  EXPECT_GE(mean, lo);
  EXPECT_LE(mean, hi);
  EXPECT_LE(j["overall"]["psnr_db"]["p5"].get<double>(), mean);
  int by_variant = 0;
  for (const char* v : {"video", "hybrid", "synthetic"})
    by_variant += j["by_variant"][v]["eye_frames"].get<int>();
  EXPECT_EQ(by_variant, 2 * kFrames);
  EXPECT_GT(j["speed"]["x_real_time"].get<double>(), 0.0);
  // m against the truth: every eye-frame with a camera measured, and a rank correlation.
  EXPECT_GT(j["m_against_truth"]["eye_frames"].get<int>(), 0);
  EXPECT_LE(j["m_against_truth"]["eye_frames"].get<int>(), 2 * kFrames);
  if (!j["m_against_truth"]["spearman_m_vs_video_error"].is_null()) {
    EXPECT_LE(std::abs(j["m_against_truth"]["spearman_m_vs_video_error"].get<double>()), 1.0);
  }
}

// The run's own transition replayed through the error models scores what the station drew: the
// frames fade the video in (hybrid, per-pixel), so the per-pixel replay is checked too.
TEST_F(ScoreRun, TheReplayedTransitionMatchesTheShownPictures) {
  const nlohmann::json j = nlohmann::json::parse(slurp(one() / "score.json"));
  EXPECT_GT(j["by_variant"]["hybrid"]["eye_frames"].get<int>(), 4);
  const nlohmann::json& check = j["tuning"]["replay_check"];
  EXPECT_LT(check["mean_abs_db"].get<double>(), 0.01);
  EXPECT_LT(check["max_abs_db"].get<double>(), 0.05);
  // Every candidate in tuning.csv, the best of each mode no worse than the run's own.
  const auto rows = rows_of(slurp(one() / "tuning.csv"));
  ASSERT_EQ(rows.size(), 1u + j["tuning"]["candidates"].get<std::size_t>());
  EXPECT_EQ(rows[0], split_csv_line("mode,m_t,eps,psnr_mean_db,psnr_p5_db,video_share"));
  const double own = j["tuning"]["this_run"]["psnr_mean_db_replayed"].get<double>();
  for (const char* mode : {"abrupt", "global_blend", "per_pixel"}) {
    double best = -1.0;
    for (std::size_t i = 1; i < rows.size(); ++i)
      if (rows[i][0] == mode) best = std::max(best, std::stod(rows[i][3]));
    EXPECT_NEAR(j["tuning"]["best"][mode]["psnr_mean_db"].get<double>(), best, 1e-4) << mode;
  }
  EXPECT_GE(j["tuning"]["best"]["per_pixel"]["psnr_mean_db"].get<double>(), own - 1e-9);
}

TEST_F(ScoreRun, ThePlotsAreWrittenAtTheirSizes) {
  const cv::Mat trace = cv::imread((one() / "score_trace.png").string());
  const cv::Mat scatter = cv::imread((one() / "m_scatter.png").string());
  EXPECT_EQ(trace.cols, 1200);
  EXPECT_EQ(trace.rows, 480);
  EXPECT_EQ(scatter.cols, 900);
  EXPECT_EQ(scatter.rows, 600);
  // The trace's plot area is shaded by variant: not the white background.
  const cv::Vec3b inside = trace.at<cv::Vec3b>(240, 600);
  EXPECT_NE(inside, cv::Vec3b(255, 255, 255));
}

}  // namespace

namespace {

// The sweep: one row per condition and method, each a run of its own, and the methods differ as
// their definitions say (video only shows the most video, synthetic only none).
TEST(ScoreSweep, EveryConditionAndMethodIsARowOfTheTable) {
  const fs::path out = suite_dir() / "sweep";
  fs::create_directories(suite_dir());
  const int rc =
      score("--sweep --scene scenes/plane.yaml --frames 6 --mono --out '" + out.string() + "'",
            suite_dir() / "sweep.log");
  ASSERT_EQ(rc, 0) << slurp(suite_dir() / "sweep.log");
  const auto rows = rows_of(slurp(out / "sweep.csv"));
  ASSERT_EQ(rows.size(), 1u + 4u * 7u);
  EXPECT_EQ(rows[0], split_csv_line("scene,condition,method,psnr_mean_db,psnr_p5_db,ssim_mean,"
                                    "ssim_p5,video_or_hybrid_share,tick_ms_per_frame,x_real_time"));
  for (std::size_t i = 1; i < rows.size(); i += 7) {
    EXPECT_EQ(rows[i][2], "video only");
    EXPECT_EQ(rows[i + 1][2], "synthetic only");
    EXPECT_GT(std::stod(rows[i][7]), 0.5) << rows[i][1];
    EXPECT_EQ(std::stod(rows[i + 1][7]), 0.0) << rows[i][1];
    for (std::size_t k = i; k < i + 7; ++k) {
      EXPECT_EQ(rows[k][0], "plane");
      EXPECT_GT(std::stod(rows[k][3]), 15.0) << rows[k][2];
      EXPECT_TRUE(fs::exists(out / "plane" / ("c" + std::to_string((i - 1) / 7)) /
                             ("m" + std::to_string(k - i)) / "score.csv"));
    }
  }
  EXPECT_NE(slurp(out / "sweep.md").find("| plane | delay 50+-20 ms / model 4 s | per-pixel"),
            std::string::npos);
  std::error_code ec;
  fs::remove_all(out, ec);
}

// The video views on the default scene's first 1.3 s (the head near camera 0, then moving away
// from it; the reconstruction has not yet placed the block): video laid on the model's surfaces
// matches the truth far better than on the plane, and the station shows the same frames as video.
TEST(ScoreVideoView, ModelDepthVideoScoresAbovePlaneVideoOnTheDefaultScene) {
  double psnr[2] = {0, 0};
  double count[2] = {0, 0};
  const char* views[2] = {"plane", "model-depth"};
  for (int i = 0; i < 2; ++i) {
    const fs::path out = suite_dir() / (std::string("view-") + views[i]);
    fs::create_directories(suite_dir());
    const fs::path log = suite_dir() / (std::string("view-") + views[i] + ".log");
    ASSERT_EQ(score(std::string("--frames 120 --video-view ") + views[i] + " --out '" +
                        out.string() + "'",
                    log),
              0)
        << slurp(log);
    const auto j = nlohmann::json::parse(slurp(out / "score.json"));
    psnr[i] = j["by_variant"]["video"]["psnr_db"]["mean"].get<double>();
    count[i] = j["by_variant"]["video"]["psnr_db"]["count"].get<double>();
    if (i == 1) {
      EXPECT_NE(slurp(log).find("video view model-depth"), std::string::npos);
    }
  }
  std::printf("    video frames: plane %.0f at %.2f dB, model-depth %.0f at %.2f dB\n", count[0],
              psnr[0], count[1], psnr[1]);
  EXPECT_GE(count[0], 60.0);
  EXPECT_EQ(count[1], count[0]);
  EXPECT_GE(psnr[1], psnr[0] + 4.0);
}

}  // namespace
