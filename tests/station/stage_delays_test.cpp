// The stage delays behind the HUD and the summary: p50s over the last second and the run against
// sorted samples, the HUD's text, and RunStages fed from hand-made latency records and model
// snapshots (each stage the time since capture).
#include "station/app/stage_delays.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "station/app/run_stages.h"

namespace hd::station {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(StageSeries, P50OverTheLastSecondTakesOnlyThatSecondsSamples) {
  StageSeries s;
  EXPECT_TRUE(std::isnan(s.p50_last_second(0)));
  // 100 ms each over 0..0.9 s, then 10 ms each over 1.0..1.9 s.
  for (int i = 0; i < 10; ++i) s.add(100.0, i * 100 * kMs);
  for (int i = 10; i < 20; ++i) s.add(10.0 + i, i * 100 * kMs);
  // At 1.95 s the last second holds 1.0..1.9 s: 20..29 ms, p50 the sample at index 5 (25).
  EXPECT_DOUBLE_EQ(s.p50_last_second(1'950 * kMs), 25.0);
  // At 1.45 s it holds 0.5..1.4 s: five of 100 ms and 20..24: index 5 of the sorted ten is 100.
  EXPECT_DOUBLE_EQ(s.p50_last_second(1'450 * kMs), 100.0);
  // NaN and negative times are not samples.
  s.add(NAN, 1'960 * kMs);
  s.add(-1.0, 1'960 * kMs);
  EXPECT_EQ(s.count(), 20u);
}

TEST(StageSeries, P50OverTheRunIsTheSortedMiddleToATenthOfAMillisecond) {
  StageSeries s;
  std::vector<double> all;
  for (int i = 0; i < 1001; ++i) {
    const double ms = 3.0 + std::fmod(i * 7.31, 40.0);  // spread over 3..43 ms
    s.add(ms, i * kMs);
    all.push_back(ms);
  }
  std::sort(all.begin(), all.end());
  EXPECT_NEAR(s.p50_run(), all[all.size() / 2], 0.05 + 1e-9);
  EXPECT_TRUE(std::isnan(StageSeries().p50_run()));
}

TEST(StageDelays, TheHudTextListsEachStageWithASampleInOrder) {
  StageDelays v = StageDelays::video();
  EXPECT_EQ(v.hud_text(0), "");
  v.stage(1).add(8.14, 0);
  v.stage(2).add(8.5, 0);
  v.stage(5).add(27.3, 0);
  EXPECT_EQ(v.hud_text(10 * kMs), "enc 8.1 > sent 8.5 > shown 27.3 ms");
  EXPECT_EQ(v.hud_text(2'000 * kMs), "");  // a second later nothing is recent
  EXPECT_EQ(StageDelays::model().names().back(), "on screen");
}

TEST(RunStages, EachStageIsTheTimeSinceCaptureFromTheRecordAndTheModel) {
  RunStages st(2);
  ModelSnapshot m;
  m.update = 4;
  m.capture_oldest_ns = 500 * kMs;
  m.reconstructed_ns = 620 * kMs;
  m.published_ns = 700 * kMs;
  const int64_t now = 2'010 * kMs;
  for (int k = 0; k < 3; ++k) {  // network video of camera 1: every link stage stamped
    const int64_t c = 1'900 * kMs + k * 33 * kMs;
    render::LatencyRecord r;
    r.video_ns = c;
    r.video_encoded_ns = c + 8 * kMs;
    r.video_sent_ns = c + 9 * kMs;
    r.video_received_ns = c + 11 * kMs;
    r.video_decoded_ns = c + 15 * kMs;
    r.predicted_display_ns = c + 30 * kMs;
    r.model_capture_ns = m.capture_oldest_ns;
    st.after_frame(r, 1, &m, now);  // the same snapshot each time: its stages once
  }
  render::LatencyRecord local;  // a camera on this host: capture and display only
  local.video_ns = 1'990 * kMs;
  local.predicted_display_ns = 2'010 * kMs;
  st.after_frame(local, 0, nullptr, now);
  const StageDelays& v = st.video(1);
  for (std::size_t i = 1; i < v.names().size(); ++i) EXPECT_EQ(v.stage(i).count(), 3u) << i;
  EXPECT_DOUBLE_EQ(v.stage(1).p50_last_second(now), 8.0);
  EXPECT_DOUBLE_EQ(v.stage(2).p50_last_second(now), 9.0);
  EXPECT_DOUBLE_EQ(v.stage(3).p50_last_second(now), 11.0);
  EXPECT_DOUBLE_EQ(v.stage(4).p50_last_second(now), 15.0);
  EXPECT_DOUBLE_EQ(v.stage(5).p50_last_second(now), 30.0);
  EXPECT_EQ(st.video(0).stage(1).count(), 0u);
  EXPECT_DOUBLE_EQ(st.video(0).stage(5).p50_last_second(now), 20.0);
  EXPECT_EQ(st.model().stage(1).count(), 1u);
  EXPECT_DOUBLE_EQ(st.model().stage(1).p50_last_second(now), 120.0);
  EXPECT_DOUBLE_EQ(st.model().stage(2).p50_last_second(now), 200.0);
  EXPECT_EQ(st.model().stage(3).count(), 3u);
  EXPECT_EQ(st.hud_text(1, {"front", "side"}, now),
            "side: enc 8.0 > sent 9.0 > recv 11.0 > dec 15.0 > shown 30.0 ms | "
            "model: recon 120.0 > model 200.0 > shown 1463.0 ms");
  EXPECT_EQ(st.hud_text(0, {"front", "side"}, now),
            "front: shown 20.0 ms | model: recon 120.0 > model 200.0 > shown 1463.0 ms");
  const std::vector<StageFigure> f = stage_figures(v);
  ASSERT_EQ(f.size(), 5u);
  EXPECT_EQ(f[0].stage, "encoded");
  EXPECT_NEAR(f[0].p50_ms, 8.0, 0.05 + 1e-9);
  EXPECT_EQ(f[4].stage, "on screen");
}

TEST(RunStages, TheGraphKeepsEachStagesLastSecondP50PerUpdateForTheChosenSource) {
  RunStages st(2);
  const std::vector<std::string> names{"front", "side"};
  EXPECT_TRUE(st.graph(names).empty());
  auto frame = [&](int camera, int64_t capture_ns, double decode_ms) {
    render::LatencyRecord r;
    r.video_ns = capture_ns;
    r.video_encoded_ns = capture_ns + 5 * kMs;
    r.video_sent_ns = capture_ns + 6 * kMs;
    r.video_received_ns = capture_ns + 7 * kMs;
    r.video_decoded_ns = capture_ns + static_cast<int64_t>(decode_ms * kMs);
    r.predicted_display_ns = capture_ns + 40 * kMs;
    st.after_frame(r, camera, nullptr, capture_ns + 40 * kMs);
  };
  // Camera 1 for 45 updates of 0.5 s; its decode stage grows by 1 ms an update.
  for (int u = 0; u < 45; ++u) {
    const int64_t t = 10'000 * kMs + u * 500 * kMs;
    frame(1, t, 10.0 + u);
    st.sample_graph(1, t + 40 * kMs);
  }
  render::HudGraph g = st.graph(names);
  EXPECT_EQ(g.title, "side: ms since capture, p50 of each second");
  EXPECT_EQ(g.names, (std::vector<std::string>{"enc", "sent", "recv", "dec", "shown"}));
  ASSERT_EQ(g.series.size(), 5u);
  ASSERT_EQ(g.series[3].size(), RunStages::kGraphSamples);  // the newest 40 of 45
  // Each update's last second holds that update's frame and the one before (0.5 s apart): the
  // p50 (upper middle of two) is the newer, 10 + u ms for update u; the oldest kept is u = 5.
  EXPECT_DOUBLE_EQ(g.series[3].front(), 15.0);
  EXPECT_DOUBLE_EQ(g.series[3].back(), 54.0);
  EXPECT_DOUBLE_EQ(g.series[0].back(), 5.0);
  EXPECT_DOUBLE_EQ(g.series[4].back(), 40.0);
  // A local camera has no link: only "shown" is in its graph, which starts again.
  render::LatencyRecord local;
  local.video_ns = 40'000 * kMs;
  local.predicted_display_ns = 40'025 * kMs;
  st.after_frame(local, 0, nullptr, 40'025 * kMs);
  st.sample_graph(0, 40'025 * kMs);
  g = st.graph(names);
  EXPECT_EQ(g.title, "front: ms since capture, p50 of each second");
  EXPECT_EQ(g.names, (std::vector<std::string>{"shown"}));
  ASSERT_EQ(g.series.size(), 1u);
  EXPECT_EQ(g.series[0], (std::vector<double>{25.0}));
}

}  // namespace
}  // namespace hd::station
