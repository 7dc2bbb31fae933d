// StreamWatchdog: when a GigE stream thread declares a stall, probes, looks for a lost camera
// and puts a wrong format right, with the real 250 ms stall timeout and 500 ms reopen period.
#include "drivers/gige/stream_watchdog.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

using Step = StreamWatchdog::Step;
using S = SourceState;

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kT0 = 10'000 * kMs;  // a monotonic time well after boot

StreamWatchdog watchdog() {
  return StreamWatchdog({250 * kMs, 500 * kMs});
}

TEST(StreamWatchdog, FramesWithinTheStallTimeoutNeedNothing) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  EXPECT_EQ(w.next(kT0 + 20 * kMs, S::kStreaming, false, false), Step::kNone);
  w.frame_at(kT0 + 200 * kMs);
  EXPECT_EQ(w.next(kT0 + 450 * kMs, S::kStreaming, false, false), Step::kNone);  // exactly 250
}

TEST(StreamWatchdog, AStallIsProbedOncePerStallTimeout) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  EXPECT_EQ(w.next(kT0 + 250 * kMs, S::kStreaming, false, false), Step::kNone);
  EXPECT_EQ(w.next(kT0 + 251 * kMs, S::kStreaming, false, false), Step::kStalledProbe);
  EXPECT_EQ(w.next(kT0 + 271 * kMs, S::kStalled, false, false), Step::kStalled);
  EXPECT_EQ(w.next(kT0 + 500 * kMs, S::kStalled, false, false), Step::kStalled);  // 249 ms
  EXPECT_EQ(w.next(kT0 + 501 * kMs, S::kStalled, false, false), Step::kStalledProbe);
  w.frame_at(kT0 + 510 * kMs);  // it was only slow
  EXPECT_EQ(w.next(kT0 + 530 * kMs, S::kStreaming, false, false), Step::kNone);
}

TEST(StreamWatchdog, ALostCameraIsLookedForEvery500Ms) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  EXPECT_EQ(w.next(kT0 + 300 * kMs, S::kDisconnected, false, false), Step::kProbeToReopen);
  EXPECT_EQ(w.next(kT0 + 320 * kMs, S::kDisconnected, false, false), Step::kNone);
  EXPECT_EQ(w.next(kT0 + 799 * kMs, S::kDisconnected, false, false), Step::kNone);
  EXPECT_EQ(w.next(kT0 + 800 * kMs, S::kDisconnected, false, false), Step::kProbeToReopen);
  // A camera released after a reconnect with other settings is looked for the same way.
  EXPECT_EQ(w.next(kT0 + 1300 * kMs, S::kFormatMismatch, true, false), Step::kProbeToReopen);
}

TEST(StreamWatchdog, ControlLostDisconnectsAStreamingButNotAnAlreadyLostCamera) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  EXPECT_EQ(w.next(kT0 + 10 * kMs, S::kStreaming, false, true), Step::kControlLost);
  EXPECT_EQ(w.next(kT0 + 10 * kMs, S::kFormatMismatch, false, true), Step::kControlLost);
  EXPECT_EQ(w.next(kT0 + 600 * kMs, S::kDisconnected, false, true), Step::kProbeToReopen);
}

TEST(StreamWatchdog, AWrongFormatIsPutRightAfter500MsAndThenEvery500Ms) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  w.mismatch_at(kT0 + 100 * kMs);
  EXPECT_EQ(w.next(kT0 + 599 * kMs, S::kFormatMismatch, false, false), Step::kNone);
  EXPECT_EQ(w.next(kT0 + 600 * kMs, S::kFormatMismatch, false, false), Step::kRestoreFormat);
  EXPECT_EQ(w.next(kT0 + 1099 * kMs, S::kFormatMismatch, false, false), Step::kNone);
  EXPECT_EQ(w.next(kT0 + 1100 * kMs, S::kFormatMismatch, false, false), Step::kRestoreFormat);
  // A mismatch is never a stall, however long since the last frame.
  EXPECT_EQ(w.next(kT0 + 1200 * kMs, S::kFormatMismatch, false, false), Step::kNone);
}

TEST(StreamWatchdog, RestartForgetsTheLastProbe) {
  StreamWatchdog w = watchdog();
  w.restart(kT0);
  EXPECT_EQ(w.next(kT0 + 300 * kMs, S::kStreaming, false, false), Step::kStalledProbe);
  w.restart(kT0 + 310 * kMs);  // stop() and start()
  // Lost at once: looked for now, not 500 ms after the probe before the restart.
  EXPECT_EQ(w.next(kT0 + 320 * kMs, S::kDisconnected, false, false), Step::kProbeToReopen);
}

}  // namespace
}  // namespace hd::drivers
