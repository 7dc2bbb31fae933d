// The CPU reference compositor as a component: the same bytes from any thread count, malformed
// requests refused and counted, and no allocation per frame (a counting allocator: every operator
// new of this test program passes through it).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstdlib>
#include <new>
#include <stdexcept>

#include "support/cpu_compositor_scenes.h"

// Counting allocator: every operator new in this binary passes through here. GCC 12 flags the
// malloc/free pairing inside replaced operators as a mismatch; it is the standard replacement.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace {

using namespace hd::render::test;

TEST(CpuCompositor, AnyThreadCountGivesTheSameBytesAsOne) {
  const Pinhole eye = pinhole(250.0, 300, 200);
  const Pinhole real = pinhole(400.0, 320, 240);
  const Frame frame = coded_frame(320, 240);
  SyntheticScene scene;
  scene.meshes.push_back(facing_quad(-1.0, -0.6, 0.8, 0.7, 2.5));
  ImageRgba8 a, b;
  a.allocate(300, 200);
  b.allocate(300, 200);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &scene;
  req.T_world_eye = look_pose(8.6, 0.0, {0.2, 0.0, 0.1});
  req.mode = TransitionMode::kPerPixel;
  req.transition = {Variant::kHybrid, 0.7, 0.3};
  req.marking.style = MarkingStyle::kChecker;
  CpuCompositor one(1);
  one.draw(req, a);
  for (const int threads : {2, 3, 8}) {
    CpuCompositor many(threads);
    b.data.assign(b.data.size(), 0);
    many.draw(req, b);
    EXPECT_EQ(a.data, b.data) << threads << " threads";
  }
  EXPECT_THROW(CpuCompositor(9), std::invalid_argument);  // refused, never quietly fewer
}

TEST(CpuCompositor, MalformedRequestsAreRejectedAndCountedWithoutTouchingTheOutput) {
  const Pinhole cam = pinhole(100.0, 64, 48);
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(64, 48);
  CompositeRequest req;
  req.eye = cam;
  req.viewport = {10, 0, 64, 48};  // sticks out of `out`
  comp.draw(req, out);
  req.viewport = {0, 0, 64, 48};
  req.eye.fx = std::nan("");
  comp.draw(req, out);
  req.eye = cam;
  req.T_world_eye.t.x() = std::numeric_limits<double>::infinity();
  comp.draw(req, out);
  EXPECT_EQ(comp.stats().requests_rejected, 3u);
  EXPECT_EQ(comp.stats().frames_drawn, 0u);
  for (uint8_t byte : out.data) ASSERT_EQ(byte, 0);

  // A frame in the wrong format or size is ignored (synthetic only) and counted.
  Frame rgb = uniform_frame(64, 48, 255, 0, 0);
  rgb.format = hd::drivers::PixelFormat::kRgb8;
  SyntheticScene scene;
  scene.background_rgb = {7, 8, 9};
  CompositeRequest vreq = video_request(cam, &rgb, cam);
  vreq.scene = &scene;
  comp.draw(vreq, out);
  Frame short_frame = uniform_frame(64, 48, 255, 0, 0);
  short_frame.data.resize(100);
  vreq.video = &short_frame;
  comp.draw(vreq, out);
  EXPECT_EQ(comp.stats().video_frames_rejected, 2u);
  EXPECT_TRUE(same_rgb(out.pixel(30, 20), 7, 8, 9));
}

TEST(CpuCompositor, DrawingAllocatesNothingAfterTheFirstFrame) {
  const Pinhole eye = pinhole(250.0, 300, 200);
  const Pinhole real = pinhole(400.0, 320, 240);
  const Frame frame = coded_frame(320, 240);
  SyntheticScene scene;
  scene.meshes.push_back(facing_quad(-1.0, -0.6, 0.8, 0.7, 2.5));
  ImageRgba8 out;
  out.allocate(300, 200);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &scene;
  req.mode = TransitionMode::kPerPixel;
  CpuCompositor comp(2);
  comp.draw(req, out);  // warm-up sizes the buffers
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 20; ++i) {
    req.transition = {Variant::kHybrid, i / 20.0, 1.0 - i / 20.0};
    req.T_world_eye = look_pose(0.5 * i, 0.0, {0.01 * i, 0.0, 0.0});
    comp.draw(req, out);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(comp.stats().frames_drawn, 21u);
}

}  // namespace
