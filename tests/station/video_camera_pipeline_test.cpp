// The station's camera pipeline: frames pass with sequence and stamps untouched, undistorted when
// the lens calls for it, the model tee keeps its rate, and nothing is allocated per frame.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/allocation_counter.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/mock/mock_camera.h"
#include "station/video/camera_pipeline.h"
#include "station/video/undistorter.h"

namespace hd::station {
namespace {

// A device whose frames the test publishes by hand (the test thread is the producer).
class HandCamera final : public drivers::CameraSource {
 public:
  HandCamera(int w, int h) : frames_(prototype(w, h)) {}
  std::string id() const override { return "hand-camera"; }
  void open() override { ++opened; }
  void start() override { ++started; }
  void stop() override { ++stopped; }
  drivers::SourceState state() const override { return drivers::SourceState::kStalled; }
  uint64_t dropped_frames() const override { return 3; }
  drivers::Mailbox<drivers::Frame>& frames() override { return frames_; }

  void push(uint64_t seq, int64_t host_ns, int64_t device_ns, bool trusted) {
    drivers::Frame& f = frames_.write_slot();
    drivers::write_test_pattern(f, seq);
    f.sequence = seq;
    f.host_timestamp_ns = host_ns;
    f.device_timestamp_ns = device_ns;
    f.device_time_trusted = trusted;
    frames_.publish();
  }
  // A frame of another size (a source whose format changed): the slot is resized for it.
  void push_sized(uint64_t seq, int w, int h) {
    drivers::Frame& f = frames_.write_slot();
    if (f.width != w || f.height != h) f.allocate_rgba(w, h);
    drivers::write_test_pattern(f, seq);
    f.sequence = seq;
    f.host_timestamp_ns = static_cast<int64_t>(seq);
    frames_.publish();
  }
  int opened = 0, started = 0, stopped = 0;

 private:
  static drivers::Frame prototype(int w, int h) {
    drivers::Frame f;
    f.allocate_rgba(w, h);
    return f;
  }
  drivers::Mailbox<drivers::Frame> frames_;
};

core::Pinhole lens(int w, int h, bool distorted) {
  core::Pinhole p = core::Pinhole::centred(0.9 * w, w, h);
  if (distorted) {
    p.distortion = {-0.25, 0.07, 0.001, -0.001, 0.0};
    p.distortion_count = 5;
  }
  return p;
}

TEST(VideoCameraPipeline, KeepsSequenceAndEveryStampAndCopiesPixelsWithoutDistortion) {
  HandCamera cam(64, 48);
  CameraPipeline pipe(cam, {lens(64, 48, false), 0.0, 500'000});
  EXPECT_FALSE(pipe.undistorting());
  const uint64_t seqs[] = {1, 2, 5, 6, 1000, 1001};  // gaps as a device with drops makes them
  int64_t host = 1'000'000'000;
  for (uint64_t s : seqs) {
    host += 16'666'667;
    cam.push(s, host, host * 3 + 11, s % 2 == 0);
    ASSERT_TRUE(pipe.process_one());
    EXPECT_FALSE(pipe.process_one());  // nothing new
    ASSERT_TRUE(pipe.frames().fetch());
    const drivers::Frame& out = pipe.frames().latest();
    EXPECT_EQ(out.sequence, s);
    EXPECT_EQ(out.host_timestamp_ns, host);
    EXPECT_EQ(out.device_timestamp_ns, host * 3 + 11);
    EXPECT_EQ(out.device_time_trusted, s % 2 == 0);
    EXPECT_EQ(drivers::read_test_pattern_sequence(out), s);
    EXPECT_EQ(out.data, cam.frames().latest().data);
  }
  EXPECT_EQ(pipe.processed(), 6u);
  EXPECT_EQ(pipe.model_published(), 6u);  // period 0: every frame also goes to the model
  EXPECT_EQ(pipe.id(), "hand-camera");
  EXPECT_EQ(pipe.state(), drivers::SourceState::kStalled);
  EXPECT_EQ(pipe.dropped_frames(), 3u);
}

TEST(VideoCameraPipeline, UndistortsWhenTheLensHasDistortionAndKeepsStamps) {
  HandCamera cam(80, 60);
  const core::Pinhole p = lens(80, 60, true);
  CameraPipeline pipe(cam, {p, 0.0, 500'000});
  EXPECT_TRUE(pipe.undistorting());
  cam.push(17, 5'000, 6'000, true);
  ASSERT_TRUE(pipe.process_one());
  ASSERT_TRUE(pipe.frames().fetch());
  drivers::Frame expect;
  expect.allocate_rgba(80, 60);
  ASSERT_TRUE(Undistorter(p).apply(cam.frames().latest(), expect));
  EXPECT_EQ(pipe.frames().latest().data, expect.data);
  EXPECT_NE(pipe.frames().latest().data, cam.frames().latest().data);
  EXPECT_EQ(pipe.frames().latest().sequence, 17u);
  EXPECT_EQ(pipe.frames().latest().host_timestamp_ns, 5'000);
  EXPECT_EQ(pipe.frames().latest().device_timestamp_ns, 6'000);
  // The model copy is the same undistorted frame.
  ASSERT_TRUE(pipe.model_frames().fetch());
  EXPECT_EQ(pipe.model_frames().latest().data, expect.data);
  EXPECT_EQ(pipe.model_frames().latest().sequence, 17u);
}

TEST(VideoCameraPipeline, ModelFramesComeAtMostOncePerPeriod) {
  HandCamera cam(32, 24);
  CameraPipeline pipe(cam, {lens(32, 24, false), 0.1, 500'000});
  // 10 s of a 60 Hz camera (frame k exposed at k * 16 666 667 ns): the 0.1 s period spans exactly
  // 6 frame intervals (6 * 16 666 667 >= 1e8 > 5 * ...), so every 6th frame goes to the model.
  std::vector<int64_t> model_stamps;
  for (uint64_t k = 0; k < 600; ++k) {
    cam.push(k, static_cast<int64_t>(k) * 16'666'667 + 1, 0, false);
    ASSERT_TRUE(pipe.process_one());
    if (pipe.model_frames().fetch()) {
      model_stamps.push_back(pipe.model_frames().latest().host_timestamp_ns);
      EXPECT_EQ(pipe.model_frames().latest().sequence, k);
    }
  }
  EXPECT_EQ(pipe.processed(), 600u);
  EXPECT_EQ(model_stamps.size(), 100u);
  for (std::size_t i = 1; i < model_stamps.size(); ++i)
    EXPECT_GE(model_stamps[i] - model_stamps[i - 1], 100'000'000);
}

TEST(VideoCameraPipeline, RejectsFramesOfTheWrongSizeAndCountsThem) {
  HandCamera cam(40, 30);
  CameraPipeline pipe(cam, {lens(64, 48, true), 0.0, 500'000});  // calibrated at another size
  cam.push(1, 10, 10, false);
  EXPECT_TRUE(pipe.process_one());
  EXPECT_FALSE(pipe.frames().fetch());
  EXPECT_EQ(pipe.rejected(), 1u);
  EXPECT_EQ(pipe.dropped_frames(), 4u);  // the device's 3 + the rejected one
  core::Pinhole bad = lens(64, 48, false);
  bad.width = 0;
  EXPECT_THROW(CameraPipeline(cam, {bad, 0.0, 500'000}), std::invalid_argument);
}

TEST(VideoCameraPipeline, AFrameOfAnotherSizeMakesTheCameraUnusableUntilTheRightSizeIsBack) {
  HandCamera cam(40, 30);
  CameraPipeline pipe(cam, {lens(40, 30, false), 0.0, 500'000});
  cam.push_sized(1, 40, 30);
  ASSERT_TRUE(pipe.process_one());
  ASSERT_TRUE(pipe.frames().fetch());
  EXPECT_EQ(pipe.state(), drivers::SourceState::kStalled);  // the source's own state

  const int64_t before_ns = drivers::monotonic_now_ns();
  cam.push_sized(2, 64, 48);
  ASSERT_TRUE(pipe.process_one());
  EXPECT_EQ(pipe.state(), drivers::SourceState::kFormatMismatch);
  EXPECT_FALSE(pipe.frames().fetch()) << "a frame of another size was published";
  drivers::FormatEvent e;
  ASSERT_TRUE(pipe.pop_format_event(e));
  EXPECT_EQ(e.kind, drivers::FormatEventKind::kLost);
  EXPECT_EQ(e.cause, drivers::FormatEventCause::kFrame);
  EXPECT_EQ(e.expected.width_px, 40);
  EXPECT_EQ(e.expected.height_px, 30);
  EXPECT_EQ(e.seen.width_px, 64);
  EXPECT_EQ(e.seen.height_px, 48);
  EXPECT_GE(e.time_ns, before_ns);
  EXPECT_LE(e.time_ns, drivers::monotonic_now_ns());
  cam.push_sized(3, 64, 48);
  ASSERT_TRUE(pipe.process_one());
  EXPECT_FALSE(pipe.pop_format_event(e)) << "one event per loss, not one per frame";
  EXPECT_EQ(pipe.rejected(), 2u);

  cam.push_sized(4, 40, 30);
  ASSERT_TRUE(pipe.process_one());
  EXPECT_EQ(pipe.state(), drivers::SourceState::kStalled);
  ASSERT_TRUE(pipe.pop_format_event(e));
  EXPECT_EQ(e.kind, drivers::FormatEventKind::kRestored);
  ASSERT_TRUE(pipe.frames().fetch());
  EXPECT_EQ(pipe.frames().latest().sequence, 4u);
  EXPECT_EQ(drivers::read_test_pattern_sequence(pipe.frames().latest()), 4u);
}

// stop() returns and leaves the source closed. How long it takes is not asserted (it was named
// "...StopsPromptly" and only recorded the time): a loaded machine stretches any such figure.
TEST(VideoCameraPipeline, ThreadForwardsAMockCameraAndStops) {
  drivers::MockCameraConfig mc;
  mc.id = "mock-pipe";
  mc.width = 64;
  mc.height = 48;
  mc.rate_hz = 200.0;
  drivers::MockCamera mock(mc);
  CameraPipeline pipe(mock, {lens(64, 48, true), 0.05, 200'000});
  pipe.open();
  pipe.start();
  uint64_t last_seq = 0;
  int got = 0;
  for (int i = 0; i < 60000 && got < 20; ++i) {  // the count only bounds a hang
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!pipe.frames().fetch()) continue;
    const drivers::Frame& f = pipe.frames().latest();
    EXPECT_TRUE(got == 0 || f.sequence > last_seq);
    EXPECT_GT(f.host_timestamp_ns, 0);
    last_seq = f.sequence;
    ++got;
  }
  EXPECT_EQ(got, 20);
  EXPECT_EQ(pipe.id(), "mock-pipe");
  EXPECT_EQ(pipe.state(), drivers::SourceState::kStreaming);
  pipe.stop();
  EXPECT_EQ(pipe.state(), drivers::SourceState::kClosed);
  EXPECT_GE(pipe.processed(), 20u);
  EXPECT_GE(pipe.model_published(), 1u);
}

TEST(VideoCameraPipeline, NoAllocationPerFrameAfterStart) {
  HandCamera cam(160, 120);
  CameraPipeline pipe(cam, {lens(160, 120, true), 0.02, 100'000});
  pipe.open();
  pipe.start();
  auto push_and_wait = [&](uint64_t k) {
    const uint64_t before = pipe.processed();
    cam.push(k, static_cast<int64_t>(k) * 10'000'000 + 1, 0, false);
    while (pipe.processed() == before) std::this_thread::yield();
  };
  for (uint64_t k = 0; k < 10; ++k) push_and_wait(k);  // warm-up
  hd::core::reset_counted_allocations();
  hd::core::count_allocations_on_all_threads(true);
  for (uint64_t k = 10; k < 210; ++k) push_and_wait(k);
  hd::core::count_allocations_on_all_threads(false);
  const uint64_t allocations = hd::core::counted_allocations();
  pipe.stop();
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(pipe.processed(), 210u);
  EXPECT_EQ(pipe.rejected(), 0u);
  // 10 ms frames, 20 ms period: every other frame went to the model.
  EXPECT_EQ(pipe.model_published(), 105u);
  EXPECT_EQ(cam.started, 1);
  EXPECT_EQ(cam.stopped, 1);
}

}  // namespace
}  // namespace hd::station
