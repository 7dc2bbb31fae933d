// Format negotiation as data: choose_v4l2_mode over hand-written mode lists.
#include "drivers/v4l2/v4l2_mode.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

namespace hd::drivers {
namespace {

constexpr uint32_t kYuyv = V4L2_PIX_FMT_YUYV;
constexpr uint32_t kMjpg = V4L2_PIX_FMT_MJPEG;
constexpr V4l2Interval k30{1, 30};
constexpr V4l2Interval k60{1, 60};
constexpr V4l2Interval k5{1, 5};

// A typical UVC webcam: YUYV is USB-bandwidth limited at large sizes, MJPEG is not.
std::vector<V4l2Mode> webcam() {
  return {{kYuyv, 640, 480, {k30, V4l2Interval{1, 15}}},
          {kYuyv, 1280, 720, {V4l2Interval{1, 10}, k5}},
          {kYuyv, 1920, 1080, {k5}},
          {kMjpg, 640, 480, {k30, k60}},
          {kMjpg, 1280, 720, {k30, k60}},
          {kMjpg, 1920, 1080, {k30}},
          {V4L2_PIX_FMT_NV12, 800, 600, {k60}}};
}

TEST(V4l2Mode, ExactSizeAndRatePrefersYuyv) {
  const auto c = choose_v4l2_mode(webcam(), {640, 480, 30.0, 0});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->fourcc, kYuyv);
  EXPECT_EQ(c->width_px, 640);
  EXPECT_EQ(c->height_px, 480);
  EXPECT_EQ(c->interval, k30);
}

TEST(V4l2Mode, MjpegWhenYuyvCannotReachTheRate) {
  const auto c = choose_v4l2_mode(webcam(), {1280, 720, 30.0, 0});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->fourcc, kMjpg);
  EXPECT_EQ(c->interval, k30);  // closest rate that reaches 30, not 60
  const auto c60 = choose_v4l2_mode(webcam(), {1280, 720, 50.0, 0});
  ASSERT_TRUE(c60);
  EXPECT_EQ(c60->interval, k60);
}

TEST(V4l2Mode, SmallestCoveringSizeThenLargestSmaller) {
  const auto c = choose_v4l2_mode(webcam(), {800, 600, 30.0, 0});
  ASSERT_TRUE(c);  // NV12 800x600 exists but cannot be converted
  EXPECT_EQ(c->width_px, 1280);
  EXPECT_EQ(c->height_px, 720);
  const auto big = choose_v4l2_mode(webcam(), {4096, 2160, 30.0, 0});
  ASSERT_TRUE(big);
  EXPECT_EQ(big->width_px, 1920);
  EXPECT_EQ(big->fourcc, kMjpg);
}

TEST(V4l2Mode, RequestedFourccIsHonoured) {
  const auto c = choose_v4l2_mode(webcam(), {640, 480, 30.0, kMjpg});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->fourcc, kMjpg);
  EXPECT_FALSE(choose_v4l2_mode(webcam(), {640, 480, 30.0, V4L2_PIX_FMT_NV12}));
}

TEST(V4l2Mode, NothingConvertibleGivesNoChoice) {
  EXPECT_FALSE(choose_v4l2_mode({}, {}));
  EXPECT_FALSE(choose_v4l2_mode({{V4L2_PIX_FMT_NV12, 640, 480, {k30}}}, {}));
}

TEST(V4l2Mode, ModeWithoutListedIntervalsIsStillUsable) {
  const auto c = choose_v4l2_mode({{kYuyv, 320, 240, {}}}, {320, 240, 30.0, 0});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->interval.numerator, 0u);
}

TEST(V4l2Mode, FourccNames) {
  EXPECT_EQ(v4l2_fourcc_name(kYuyv), "YUYV");
  EXPECT_EQ(v4l2_fourcc_name(kMjpg), "MJPG");
  EXPECT_EQ(v4l2_pixel_format(kYuyv), PixelFormat::kYuyv);
  EXPECT_EQ(v4l2_pixel_format(kMjpg), PixelFormat::kMjpeg);
}

}  // namespace
}  // namespace hd::drivers
