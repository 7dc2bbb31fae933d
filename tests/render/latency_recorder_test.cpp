// LatencyRecorder: percentiles against a plain sorted-array computation, CSV round trip, PNG.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "render/latency/latency_recorder.h"

namespace hd::render {
namespace {

namespace fs = std::filesystem;

LatencyRecord make(uint64_t frame, int64_t mtp_ns, int64_t age_ns) {
  LatencyRecord r;
  r.frame = frame;
  r.pose_sample_ns = 1'000'000'000 + static_cast<int64_t>(frame) * 11'111'111;
  r.predicted_display_ns = r.pose_sample_ns + mtp_ns;
  r.swap_ns = r.predicted_display_ns - 3'000'000;
  r.render_start_ns = r.pose_sample_ns + 100'000;
  r.render_end_ns = r.render_start_ns + 2'000'000;
  r.texture_update_ns = r.render_start_ns;
  if (age_ns > 0) r.video_ns = r.predicted_display_ns - age_ns;
  r.video_is_exposure = frame % 2 == 0;
  r.missed_deadline = frame % 17 == 0;
  if (age_ns > 0 && frame % 5 == 0) {  // a network camera's video: its link's stages
    r.video_encoded_ns = r.video_ns + 4'000'000;
    r.video_sent_ns = r.video_encoded_ns + 300'000;
    r.video_received_ns = r.video_sent_ns + 1'200'000;
    r.video_decoded_ns = r.video_received_ns + 2'500'000;
  }
  if (frame % 3 == 0) {  // an updated model's stages
    r.model_capture_ns = r.predicted_display_ns - 900'000'000;
    r.model_reconstructed_ns = r.model_capture_ns + 120'000'000;
    r.model_published_ns = r.model_reconstructed_ns + 80'000'000;
  }
  return r;
}

// Nearest rank on a sorted copy, written out plainly.
double rank_ms(std::vector<int64_t> v, double p) {
  std::sort(v.begin(), v.end());
  std::size_t k = static_cast<std::size_t>(std::ceil(p / 100.0 * v.size()));
  if (k < 1) k = 1;
  return v[k - 1] * 1e-6;
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("hd_latency_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

RC_GTEST_PROP(LatencyRecorder, PercentilesMatchSortedArray, ()) {
  const auto values =
      *rc::gen::nonEmpty(rc::gen::container<std::vector<int>>(rc::gen::inRange(1, 100'000'000)));
  LatencyRecorder rec(values.size());
  std::vector<int64_t> plain;
  for (std::size_t i = 0; i < values.size(); ++i) {
    rec.record(make(i, values[i], 0));
    plain.push_back(values[i]);
  }
  const LatencyStats s = rec.stats(LatencyMetric::kMotionToDisplay);
  RC_ASSERT(s.count == values.size());
  RC_ASSERT(s.p50_ms == rank_ms(plain, 50));
  RC_ASSERT(s.p95_ms == rank_ms(plain, 95));
  RC_ASSERT(s.p99_ms == rank_ms(plain, 99));
  RC_ASSERT(s.max_ms == *std::max_element(plain.begin(), plain.end()) * 1e-6);
  RC_ASSERT(rec.stats(LatencyMetric::kVideoAge).count == 0u);  // no video stamps: no samples
}

TEST(LatencyRecorder, KeepsTheNewestRecordsWhenFull) {
  LatencyRecorder rec(10);
  for (uint64_t i = 0; i < 25; ++i) rec.record(make(i, 1'000'000 * (i + 1), 0));
  EXPECT_EQ(rec.size(), 10u);
  EXPECT_EQ(rec.overwritten(), 15u);
  EXPECT_EQ(rec.at(0).frame, 15u);
  EXPECT_EQ(rec.at(9).frame, 24u);
  EXPECT_DOUBLE_EQ(rec.stats(LatencyMetric::kMotionToDisplay).max_ms, 25.0);
  EXPECT_EQ(rec.missed_deadlines(), 2u);  // frames 0 and 17
}

TEST(LatencyRecorder, CsvRoundTripIsExactAndAtomic) {
  const fs::path dir = temp_dir();
  LatencyRecorder rec(100);
  std::mt19937 rng(1);
  for (uint64_t i = 0; i < 100; ++i)
    rec.record(make(i, 5'000'000 + rng() % 20'000'000, i % 3 ? 30'000'000 + rng() % 9'000'000 : 0));
  const std::string path = (dir / "latency.csv").string();
  rec.write_csv(path);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const auto back = LatencyRecorder::read_csv(path);
  ASSERT_EQ(back.size(), 100u);
  for (std::size_t i = 0; i < back.size(); ++i) {
    const LatencyRecord& a = rec.at(i);
    const LatencyRecord& b = back[i];
    EXPECT_EQ(a.frame, b.frame);
    EXPECT_EQ(a.pose_sample_ns, b.pose_sample_ns);
    EXPECT_EQ(a.video_ns, b.video_ns);
    EXPECT_EQ(a.video_is_exposure, b.video_is_exposure);
    EXPECT_EQ(a.texture_update_ns, b.texture_update_ns);
    EXPECT_EQ(a.render_start_ns, b.render_start_ns);
    EXPECT_EQ(a.render_end_ns, b.render_end_ns);
    EXPECT_EQ(a.swap_ns, b.swap_ns);
    EXPECT_EQ(a.predicted_display_ns, b.predicted_display_ns);
    EXPECT_EQ(a.missed_deadline, b.missed_deadline);
    EXPECT_EQ(a.video_encoded_ns, b.video_encoded_ns);
    EXPECT_EQ(a.video_sent_ns, b.video_sent_ns);
    EXPECT_EQ(a.video_received_ns, b.video_received_ns);
    EXPECT_EQ(a.video_decoded_ns, b.video_decoded_ns);
    EXPECT_EQ(a.model_capture_ns, b.model_capture_ns);
    EXPECT_EQ(a.model_reconstructed_ns, b.model_reconstructed_ns);
    EXPECT_EQ(a.model_published_ns, b.model_published_ns);
  }
  fs::remove_all(dir);
}

TEST(LatencyRecorder, MalformedCsvIsRejectedWithFileAndLine) {
  const fs::path dir = temp_dir();
  LatencyRecorder rec(4);
  rec.record(make(1, 1000, 0));
  const std::string path = (dir / "bad.csv").string();
  rec.write_csv(path);
  {
    std::ofstream f(path, std::ios::app);
    f << "2,3,x,0,0,0,0,0,0,0\n";
  }
  try {
    LatencyRecorder::read_csv(path);
    FAIL() << "accepted a bad cell";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3: column 3"), std::string::npos) << e.what();
  }
  {
    std::ofstream f(path, std::ios::trunc);
    f << "nonsense\n";
  }
  EXPECT_THROW(LatencyRecorder::read_csv(path), std::runtime_error);
  EXPECT_THROW(LatencyRecorder::read_csv((dir / "missing.csv").string()), std::runtime_error);
  fs::remove_all(dir);
}

TEST(LatencyRecorder, HudLineShowsNewestFrame) {
  LatencyRecorder rec(8);
  rec.record(make(41, 12'500'000, 30'000'000));
  const std::string hud(rec.hud_line());
  EXPECT_NE(hud.find("frame 41"), std::string::npos) << hud;
  EXPECT_NE(hud.find("MTP display 12.5 ms"), std::string::npos) << hud;
  EXPECT_NE(hud.find("MTP swap 9.5 ms"), std::string::npos) << hud;
  EXPECT_NE(hud.find("video age 30.0 ms"), std::string::npos) << hud;
}

TEST(LatencyRecorder, TheLinkStagesOfNetworkVideoAddUpToItsAge) {
  LatencyRecorder rec(100);
  for (uint64_t i = 0; i < 100; ++i) rec.record(make(i, 14'000'000, 35'000'000));
  // Every fifth record is network video (make()): 4 + 0.3 + 1.2 + 2.5 ms, and the rest of the
  // 35 ms age between decode and display.
  EXPECT_EQ(rec.stats(LatencyMetric::kLinkEncode).count, 20u);
  EXPECT_NEAR(rec.stats(LatencyMetric::kLinkEncode).p50_ms, 4.0, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kLinkSend).p50_ms, 0.3, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kLinkNetwork).p50_ms, 1.2, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kLinkDecode).p50_ms, 2.5, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kLinkShow).p50_ms, 35.0 - 4.0 - 0.3 - 1.2 - 2.5, 1e-9);
  EXPECT_EQ(rec.stats(LatencyMetric::kVideoAge).count, 100u);
}

TEST(LatencyRecorder, TheModelStagesAddUpToItsAge) {
  LatencyRecorder rec(99);
  for (uint64_t i = 0; i < 99; ++i) rec.record(make(i, 14'000'000, 35'000'000));
  // Every third record drew an updated model (make()): reconstructed 120 ms after its capture,
  // in the model 80 ms later, shown 900 ms after capture; the others drew the a-priori model.
  EXPECT_EQ(rec.stats(LatencyMetric::kModelPublish).count, 33u);
  EXPECT_NEAR(rec.stats(LatencyMetric::kModelReconstruct).p50_ms, 120.0, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kModelPublish).p50_ms, 200.0, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kModelShow).p50_ms, 700.0, 1e-9);
  EXPECT_NEAR(rec.stats(LatencyMetric::kModelAge).p50_ms, 900.0, 1e-9);
  EXPECT_EQ(rec.stats(LatencyMetric::kModelAge).count, 33u);
}

TEST(LatencyRecorder, PngIsWritten) {
  const fs::path dir = temp_dir();
  LatencyRecorder rec(600);
  for (uint64_t i = 0; i < 600; ++i)
    rec.record(make(i, 14'000'000 + static_cast<int64_t>(3e6 * std::sin(i * 0.05)),
                    35'000'000 + (i % 11) * 1'000'000));
  const std::string path = (dir / "latency.png").string();
  rec.write_png(path);
  EXPECT_FALSE(fs::exists(path + ".tmp.png"));
  const cv::Mat img = cv::imread(path);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1400);
  EXPECT_EQ(img.rows, 560);
  // Something other than the white background was drawn in the plot area.
  EXPECT_LT(cv::mean(img)[0], 254.0);
  if (const char* keep = std::getenv("HD_KEEP_PNG"))
    fs::copy_file(path, keep, fs::copy_options::overwrite_existing);
  fs::remove_all(dir);
}

TEST(LatencyRecorder, UnwritableDirectoryThrowsNamingTheFile) {
  LatencyRecorder rec(2);
  rec.record(make(0, 1, 0));
  try {
    rec.write_csv("/nonexistent-dir/x.csv");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.csv"), std::string::npos);
  }
  EXPECT_THROW(rec.write_png("/nonexistent-dir/x.png"), std::runtime_error);
}

}  // namespace
}  // namespace hd::render
