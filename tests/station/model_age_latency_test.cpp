// Model age in the latency log: the metric's closed form and the CSV column round trip.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "render/latency/latency_recorder.h"

namespace hd::station {
namespace {

TEST(ModelAgeLatency, AgeIsDisplayTimeMinusCaptureAndAbsentForTheAprioriModel) {
  render::LatencyRecord r;
  r.predicted_display_ns = 5'000'000'000;
  int64_t age = 0;
  EXPECT_FALSE(latency_of(r, render::LatencyMetric::kModelAge, age));  // no update drawn yet
  r.model_capture_ns = 4'250'000'000;
  ASSERT_TRUE(latency_of(r, render::LatencyMetric::kModelAge, age));
  EXPECT_EQ(age, 750'000'000);
}

TEST(ModelAgeLatency, CsvCarriesTheModelCaptureTime) {
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("hd_model_age_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir);
  render::LatencyRecorder rec(8);
  for (int i = 0; i < 5; ++i) {
    render::LatencyRecord r;
    r.frame = static_cast<uint64_t>(i);
    r.pose_sample_ns = 1000 + i;
    r.predicted_display_ns = 2'000'000'000 + i * 11'111'111;
    r.model_capture_ns = i == 0 ? 0 : 1'500'000'000 + (i / 2) * 250'000'000;
    rec.record(r);
  }
  const std::string path = (dir / "latency.csv").string();
  rec.write_csv(path);
  std::ifstream f(path);
  std::string header;
  std::getline(f, header);
  EXPECT_NE(header.find("model_capture_ns"), std::string::npos);
  const auto back = render::LatencyRecorder::read_csv(path);
  ASSERT_EQ(back.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_EQ(back[i].model_capture_ns, rec.at(i).model_capture_ns);
  const render::LatencyStats s = rec.stats(render::LatencyMetric::kModelAge);
  EXPECT_EQ(s.count, 4u);
  // Ages: 511.1, 272.2, 283.3, 44.4 ms -> max 511.1 ms.
  EXPECT_NEAR(s.max_ms, 511.111111, 1e-6);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hd::station
