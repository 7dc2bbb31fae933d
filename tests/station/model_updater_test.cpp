// The delayed model: updates on the refresh grid, the staleness delay between taking frames and
// publishing, moving objects placed at the frames' capture time, textures from the frames.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <vector>

#include "render/loop/stepped_clock.h"
#include "station/model/model_updater.h"
#include "test_wait.h"

namespace hd::station {
namespace {

// Time moves only when the updater sleeps: every wait ends exactly at its deadline, so the
// schedule can be asserted to the nanosecond without depending on the machine's speed.
using FakeClock = render::SteppedLoopClock;

render::SyntheticScene plane_scene() {
  render::SyntheticScene s;
  render::TexturedMesh m;
  m.positions_m = {{-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(32, 32);  // transparent black: "nothing seen yet"
  s.meshes.push_back(std::move(m));
  s.revision = 7;
  return s;
}

drivers::Frame uniform_frame(int w, int h, uint8_t r, uint8_t g, uint8_t b, int64_t t_ns) {
  drivers::Frame f;
  f.allocate_rgba(w, h);
  for (std::size_t p = 0; p < f.data.size(); p += 4) {
    f.data[p] = r;
    f.data[p + 1] = g;
    f.data[p + 2] = b;
    f.data[p + 3] = 255;
  }
  f.host_timestamp_ns = t_ns;
  f.sequence = 1;
  return f;
}

struct MoveCall {
  int64_t capture_ns, now_ns;
};

TEST(ModelUpdater, PublishesOnThePeriodGridAfterTheDelayWithObjectsAtCaptureTime) {
  const core::Pinhole k = core::Pinhole::centred(200, 320, 240);
  drivers::Mailbox<drivers::Frame> frames(uniform_frame(320, 240, 0, 0, 0, 0));
  {
    frames.write_slot() = uniform_frame(320, 240, 30, 160, 90, 4'000'000'000);
    frames.publish();
  }
  const ModelCamera cams[] = {{&frames, k, core::Pose::identity()}};
  FakeClock clock(10'000'000'000);
  std::mutex mu;
  std::vector<MoveCall> calls;
  ModelUpdaterConfig cfg;
  cfg.refresh_period_s = 0.25;
  cfg.delay_s = 0.1;
  cfg.move_objects = [&](render::SyntheticScene& model, int64_t capture_ns) {
    const std::lock_guard lock(mu);
    calls.push_back({capture_ns, clock.now_ns()});
    for (auto& p : model.meshes[0].positions_m) p.x() += 0.01f;  // the object moves 1 cm each time
  };
  ModelUpdater updater(plane_scene(), cams, cfg, clock);
  // Before any update the station sees the a-priori model.
  EXPECT_EQ(updater.models().latest().scene.revision, 7u);
  EXPECT_EQ(updater.models().latest().capture_oldest_ns, 0);

  updater.start();
  // The fake clock runs as fast as the updater thread does; this only waits for that thread.
  ASSERT_TRUE(eventually([&] { return updater.stats().updates >= 6; }));
  updater.stop();
  const ModelUpdaterStats st = updater.stats();
  ASSERT_GE(st.updates, 6u);
  ASSERT_EQ(calls.size(), st.updates);
  for (std::size_t i = 0; i < calls.size(); ++i) {
    // Update i takes frames at t0 + i * period and moves the objects after the delay.
    EXPECT_EQ(calls[i].now_ns,
              10'000'000'000 + static_cast<int64_t>(i) * 250'000'000 + 100'000'000);
    EXPECT_EQ(calls[i].capture_ns, 4'000'000'000);
  }
  EXPECT_EQ(st.skipped_periods, 0u);

  ASSERT_TRUE(updater.models().fetch());
  const ModelSnapshot& s = updater.models().latest();
  EXPECT_EQ(s.update, st.updates);
  EXPECT_EQ(s.scene.revision, 7u + st.updates);
  EXPECT_EQ(s.capture_oldest_ns, 4'000'000'000);
  EXPECT_EQ(s.capture_newest_ns, 4'000'000'000);
  EXPECT_EQ(s.published_ns - s.taken_ns, 100'000'000);  // the configured staleness delay
  EXPECT_EQ(s.taken_ns, 10'000'000'000 + static_cast<int64_t>(st.updates - 1) * 250'000'000);
  // The published geometry is where the callback put it, the texture is the frame's colour.
  EXPECT_NEAR(s.scene.meshes[0].positions_m[0].x(), -1.0 + 0.01 * st.updates, 1e-5);
  const uint8_t* t = s.scene.meshes[0].texture.pixel(16, 16);
  EXPECT_EQ(t[0], 30);
  EXPECT_EQ(t[1], 160);
  EXPECT_EQ(t[2], 90);
  EXPECT_EQ(t[3], 255);
  EXPECT_EQ(st.last_texels_updated, 32u * 32u);
}

TEST(ModelUpdater, LateUpdatesSkipPeriodsAndTheOldestFrameSetsTheAge) {
  const core::Pinhole k = core::Pinhole::centred(200, 320, 240);
  drivers::Mailbox<drivers::Frame> f1(uniform_frame(320, 240, 0, 0, 0, 0));
  drivers::Mailbox<drivers::Frame> f2(uniform_frame(320, 240, 0, 0, 0, 0));
  drivers::Mailbox<drivers::Frame> never(uniform_frame(320, 240, 0, 0, 0, 0));
  f1.write_slot() = uniform_frame(320, 240, 10, 10, 10, 5'000);
  f1.publish();
  f2.write_slot() = uniform_frame(320, 240, 20, 20, 20, 9'000);
  f2.publish();
  const ModelCamera cams[] = {{&f1, k, core::Pose::identity()},
                              {&never, k, core::Pose::identity()},
                              {&f2, k, core::Pose::identity()}};
  FakeClock clock(1'000'000'000);
  ModelUpdaterConfig cfg;
  cfg.refresh_period_s = 0.1;
  cfg.delay_s = 0.25;  // longer than the period: two grid slots pass during every update
  ModelUpdater updater(plane_scene(), cams, cfg, clock);
  updater.start();
  ASSERT_TRUE(eventually([&] { return updater.stats().updates >= 4; }));
  updater.stop();
  const ModelUpdaterStats st = updater.stats();
  // Update i runs from t0 + 3 i periods to 0.25 s later; slots 3i+1 and 3i+2 are skipped.
  // (the skips after the last update may not be counted yet when stop() ends the loop)
  EXPECT_GE(st.skipped_periods, 2u * (st.updates - 1));
  EXPECT_LE(st.skipped_periods, 2u * st.updates);
  ASSERT_TRUE(updater.models().fetch());
  const ModelSnapshot& s = updater.models().latest();
  EXPECT_EQ(s.taken_ns, 1'000'000'000 + static_cast<int64_t>(st.updates - 1) * 300'000'000);
  EXPECT_EQ(s.capture_oldest_ns, 5'000);  // the camera without frames is left out
  EXPECT_EQ(s.capture_newest_ns, 9'000);
  // Both cameras see the plane head-on at the same angle: the first one listed wins the tie.
  EXPECT_EQ(s.scene.meshes[0].texture.pixel(5, 5)[0], 10);
}

TEST(ModelUpdater, NoFramesNoPublicationAndSlotsAreNeverReallocated) {
  const core::Pinhole k = core::Pinhole::centred(200, 320, 240);
  drivers::Mailbox<drivers::Frame> frames(uniform_frame(320, 240, 0, 0, 0, 0));
  const ModelCamera cams[] = {{&frames, k, core::Pose::identity()}};
  FakeClock clock(1);
  ModelUpdater updater(plane_scene(), cams, {}, clock);
  EXPECT_FALSE(updater.update_once());
  EXPECT_EQ(updater.stats().updates_without_frames, 1u);
  EXPECT_FALSE(updater.models().fetch());

  std::set<const uint8_t*> buffers;
  for (int i = 0; i < 12; ++i) {
    frames.write_slot() = uniform_frame(320, 240, static_cast<uint8_t>(i), 0, 0, 100 + i);
    frames.publish();
    ASSERT_TRUE(updater.update_once());
    ASSERT_TRUE(updater.models().fetch());
    const ModelSnapshot& s = updater.models().latest();
    EXPECT_EQ(s.scene.meshes[0].texture.pixel(3, 3)[0], i);
    EXPECT_EQ(s.capture_oldest_ns, 100 + i);
    buffers.insert(s.scene.meshes[0].texture.data.data());
  }
  EXPECT_EQ(buffers.size(), 3u);  // the three slots made at construction, reused
}

TEST(ModelUpdater, ASteppedUpdatePublishesAtFinishWhatWasTakenAtTake) {
  const core::Pinhole k = core::Pinhole::centred(200, 320, 240);
  drivers::Mailbox<drivers::Frame> frames(uniform_frame(320, 240, 0, 0, 0, 0));
  const ModelCamera cams[] = {{&frames, k, core::Pose::identity()}};
  FakeClock clock(2'000'000'000);
  ModelUpdaterConfig cfg;
  cfg.delay_s = 0.3;
  ModelUpdater updater(plane_scene(), cams, cfg, clock);
  EXPECT_FALSE(updater.take_update());  // nothing yet: counted, nothing to finish
  EXPECT_EQ(updater.stats().updates_without_frames, 1u);
  frames.write_slot() = uniform_frame(320, 240, 40, 0, 0, 1'900'000'000);
  frames.publish();
  ASSERT_TRUE(updater.take_update());
  // A newer frame arrives while the update waits out its delay: it is not the one used.
  frames.write_slot() = uniform_frame(320, 240, 90, 0, 0, 2'100'000'000);
  frames.publish();
  EXPECT_FALSE(updater.models().fetch()) << "nothing is published before finish";
  clock.set_ns(2'300'000'000);  // the driver's delay on the scene's clock
  updater.finish_update();
  ASSERT_TRUE(updater.models().fetch());
  const ModelSnapshot& s = updater.models().latest();
  EXPECT_EQ(s.taken_ns, 2'000'000'000);
  EXPECT_EQ(s.published_ns, 2'300'000'000);
  EXPECT_EQ(s.capture_oldest_ns, 1'900'000'000);
  EXPECT_EQ(s.scene.meshes[0].texture.pixel(3, 3)[0], 40);
  EXPECT_EQ(updater.stats().updates, 1u);
}

TEST(ModelUpdater, RealClockDelayIsAtLeastTheConfiguredOne) {
  const core::Pinhole k = core::Pinhole::centred(200, 320, 240);
  drivers::Mailbox<drivers::Frame> frames(uniform_frame(320, 240, 0, 0, 0, 0));
  render::MonotonicLoopClock clock;
  frames.write_slot() = uniform_frame(320, 240, 1, 2, 3, clock.now_ns());
  frames.publish();
  const ModelCamera cams[] = {{&frames, k, core::Pose::identity()}};
  ModelUpdaterConfig cfg;
  cfg.refresh_period_s = 0.05;
  cfg.delay_s = 0.02;
  ModelUpdater updater(plane_scene(), cams, cfg, clock);
  updater.start();
  std::vector<ModelSnapshot> seen;
  ASSERT_TRUE(eventually([&] {
    if (updater.models().fetch()) seen.push_back(updater.models().latest());
    return seen.size() >= 3;
  }));
  updater.stop();
  // A lower bound only: a loaded machine makes the delay longer, never shorter.
  for (const ModelSnapshot& s : seen) EXPECT_GE(s.published_ns - s.taken_ns, 20'000'000);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i].update, seen[i - 1].update);
}

TEST(ModelUpdater, RejectsBadPeriodsAndDelays) {
  FakeClock clock(1);
  ModelUpdaterConfig cfg;
  cfg.refresh_period_s = 0;
  EXPECT_THROW(ModelUpdater(plane_scene(), {}, cfg, clock), std::invalid_argument);
  cfg.refresh_period_s = NAN;
  EXPECT_THROW(ModelUpdater(plane_scene(), {}, cfg, clock), std::invalid_argument);
  cfg.refresh_period_s = 1;
  cfg.delay_s = -0.1;
  EXPECT_THROW(ModelUpdater(plane_scene(), {}, cfg, clock), std::invalid_argument);
}

}  // namespace
}  // namespace hd::station
