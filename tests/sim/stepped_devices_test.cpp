// The scene's devices on the scene's clock: SteppedCamera delivers what the device's thread would
// have by each time (in order, after its delay, never a dropped frame), SteppedHead publishes the
// tracker's samples on its grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>

#include "sim/scene/scene_file.h"
#include "sim/simulation.h"
#include "sim/stepped_camera.h"
#include "sim/stepped_head.h"
#include "test_paths.h"

namespace hd::sim {
namespace {

constexpr int64_t kEpochNs = 7'000'000'000;  // any host time; not 0 (0 means "no frame")

Scene scene(const std::string& name) {
  return load_scene(std::string(hd::test::source_dir()) + "/scenes/" + name);
}

TEST(SteppedCamera, DeliversTheNewestFrameDueByEachStepInOrderAndNeverADroppedOne) {
  Simulation sim(scene("all-effects.yaml"));  // camera and network delay, 3 % drops
  SteppedCamera cam(sim, 0, kEpochNs);
  cam.start();
  // The device's rule, written out: frames leave in sequence order, each at the later of its
  // exposure + delays and the previous one's departure; a drop delivers nothing.
  uint64_t seq = 0, drops_due = 0;
  int64_t last = 0;
  int64_t expected_newest = -1;
  int checked = 0;
  for (int step = 0; step < 40; ++step) {
    const int64_t now = kEpochNs + int64_t(step) * 100'000'000;  // every 0.1 s for 4 s
    for (;; ++seq) {
      const SimFrameTiming t = sim.frame_timing(0, seq);
      const int64_t due = std::max(kEpochNs + t.exposure_offset_ns + t.delivery_delay_ns, last);
      if (due > now) break;
      last = due;
      if (t.dropped)
        ++drops_due;
      else
        expected_newest = static_cast<int64_t>(seq);
    }
    const bool published = cam.advance_to(now);
    EXPECT_EQ(cam.dropped_frames(), drops_due) << "at step " << step;
    if (expected_newest < 0) {
      EXPECT_FALSE(published);
      continue;
    }
    if (published) {
      ASSERT_TRUE(cam.frames().fetch());
      const drivers::Frame& f = cam.frames().latest();
      EXPECT_EQ(f.sequence, static_cast<uint64_t>(expected_newest)) << "at step " << step;
      EXPECT_FALSE(sim.frame_timing(0, f.sequence).dropped);
      EXPECT_EQ(f.host_timestamp_ns, kEpochNs + sim.frame_timing(0, f.sequence).exposure_offset_ns);
      EXPECT_LE(f.host_timestamp_ns, now);
      ++checked;
    }
  }
  EXPECT_GE(checked, 39);  // 30 Hz in 0.1 s steps: a new frame in every step after the first
  // 120 frames at 3 %: this seed drops some, so the rule for drops was exercised.
  EXPECT_GT(drops_due, 0u);
  // Delivery lags exposure by the delays: the first frame (exposed at 0) arrives at >= 20 ms.
  SteppedCamera late(sim, 0, kEpochNs);
  late.start();
  EXPECT_FALSE(late.advance_to(kEpochNs + 19'000'000));
}

TEST(SteppedCamera, FramesAreTheSimulatorsOwnPixels) {
  Simulation a(scene("default.yaml")), b(scene("default.yaml"));
  SteppedCamera cam(a, 1, kEpochNs);
  cam.start();
  ASSERT_TRUE(cam.advance_to(kEpochNs + 500'000'000));
  ASSERT_TRUE(cam.frames().fetch());
  const drivers::Frame& f = cam.frames().latest();
  drivers::Frame expected;
  b.render_frame(1, f.sequence, expected);
  ASSERT_EQ(f.data.size(), expected.data.size());
  EXPECT_EQ(std::memcmp(f.data.data(), expected.data.data(), f.data.size()), 0);
  EXPECT_EQ(cam.id(), "sim:cam1");
}

TEST(SteppedHead, PublishesTheTrackersSamplesOnItsGridWithTheSceneEffects) {
  Simulation sim(scene("all-effects.yaml"));  // tracker noise and drift
  ASSERT_EQ(sim.scene().head.rate_hz, 500.0);
  SteppedHead head(sim, kEpochNs);
  head.start();
  EXPECT_EQ(head.advance_to(kEpochNs + 100'000'000), 51u);  // t = 0, 2, ..., 100 ms
  drivers::PoseSample s;
  uint64_t n = 0;
  while (head.history().pop(s)) {
    EXPECT_EQ(s.sequence, n);
    EXPECT_EQ(s.host_timestamp_ns, kEpochNs + int64_t(n) * 2'000'000);
    ++n;
  }
  EXPECT_EQ(n, 51u);
  ASSERT_TRUE(head.latest().fetch());
  const drivers::PoseSample expected = sim.head_sample(0.1, 50);
  EXPECT_EQ((head.latest().latest().T_tracker_head.t - expected.T_tracker_head.t).norm(), 0.0);
  EXPECT_EQ((head.latest().latest().T_tracker_head.R - expected.T_tracker_head.R).norm(), 0.0);
  EXPECT_EQ(head.advance_to(kEpochNs + 101'000'000), 0u);
  EXPECT_EQ(head.advance_to(kEpochNs + 102'000'000), 1u);
}

}  // namespace
}  // namespace hd::sim
