// The per-frame path (poll, DQBUF, convert into the mailbox slot, publish, QBUF) does not
// allocate: every operator new in this program is counted, and after warm-up the count must not
// move while frames flow. (libjpeg's own malloc'd pools are outside operator new: see
// MjpegDecoder's comment.)
#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "core/allocation_counter.h"
#include "drivers/v4l2/v4l2_camera.h"
#include "fake_v4l2_device.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

// Every operator new in this program counts (hd_allocation_counter).
const bool kCountingEverywhere = (core::count_allocations_on_all_threads(true), true);

// Waits for the capture thread (eventually's 60 s bounds a hang only; the caller asserts the
// count).
void wait_for_frames(Mailbox<Frame>& mb, uint64_t n) {
  eventually([&] { return mb.published() >= n; });
}

uint64_t allocations_while_streaming(testing::FakeV4l2Config cfg, int w, int h) {
  testing::FakeV4l2Device fake(cfg);
  V4l2CameraOptions opt;
  opt.mode = {w, h, 30.0, 0};
  opt.poll_timeout_ms = 10;
  V4l2Camera cam(cfg.path, opt, fake);
  cam.start();
  wait_for_frames(cam.frames(), 10);  // warm-up
  const uint64_t before = hd::core::counted_allocations();
  const uint64_t published_before = cam.frames().published();
  wait_for_frames(cam.frames(), published_before + 50);
  const uint64_t after = hd::core::counted_allocations();
  EXPECT_GE(cam.frames().published(), published_before + 50);
  cam.stop();
  return after - before;
}

TEST(V4l2CameraAllocation, YuyvPerFramePathDoesNotAllocate) {
  testing::FakeV4l2Config cfg;
  cfg.error_at = {20, 30};  // fault paths are per-frame paths too
  cfg.skip_before = {{25, 2}};
  EXPECT_EQ(allocations_while_streaming(cfg, 32, 16), 0u);
}

TEST(V4l2CameraAllocation, MjpegPerFramePathDoesNotAllocate) {
  std::vector<uint8_t> rgba(64 * 32 * 4, 128);
  tjhandle tj = tjInitCompress();
  unsigned char* out = nullptr;
  unsigned long len = 0;
  ASSERT_EQ(tjCompress2(tj, rgba.data(), 64, 64 * 4, 32, TJPF_RGBA, &out, &len, TJSAMP_422, 90, 0),
            0);
  testing::FakeV4l2Config cfg;
  cfg.modes = {{V4L2_PIX_FMT_MJPEG, 64, 32, {{1, 30}}}};
  cfg.mjpeg_frames = {std::vector<uint8_t>(out, out + len)};
  tjFree(out);
  tjDestroy(tj);
  EXPECT_EQ(allocations_while_streaming(cfg, 64, 32), 0u);
}

TEST(V4l2CameraAllocation, TheCounterSeesAllocations) {
  const uint64_t before = hd::core::counted_allocations();
  // Direct calls: unlike new-expressions, the compiler may not elide them.
  void* a = ::operator new(16);
  void* b = ::operator new(400);
  ::operator delete(a);
  ::operator delete(b);
  EXPECT_EQ(hd::core::counted_allocations() - before, 2u);
}

}  // namespace
}  // namespace hd::drivers
