// The negotiation rule on plain data: exact size, an acceptable pixel format, unknown passes.
#include "drivers/camera_format.h"

#include <gtest/gtest.h>

#include "drivers/format_event.h"
#include "drivers/source_state.h"

namespace hd::drivers {
namespace {

FormatNegotiation answer(int w, int h, PixelFormat f = PixelFormat::kMono8) {
  return {CameraFormat{w, h, f, 30.0}, "", "", ""};
}

TEST(CameraFormat, TheExactSizeIsAcceptedAndAnyOtherIsRefusedWithBothSizes) {
  const CameraFormatRequest want{640, 480, {}, 0.0};
  EXPECT_TRUE(judge_format(want, answer(640, 480)).ok);
  for (auto [w, h] : {std::pair{1280, 960}, {320, 240}, {640, 481}, {480, 640}}) {
    const FormatVerdict v = judge_format(want, answer(w, h));
    EXPECT_FALSE(v.ok) << w << "x" << h;
    EXPECT_EQ(v.problem, "delivers " + std::to_string(w) + "x" + std::to_string(h) +
                             ", not the requested 640x480");
  }
}

TEST(CameraFormat, TheDevicesReasonAndLimitsAreQuoted) {
  FormatNegotiation n = answer(512, 512);
  n.refused = "Width 4000 is outside the camera's 1..2048";
  n.limits = "1..2048 x 1..2048 px";
  EXPECT_EQ(judge_format({4000, 3000, {}, 0.0}, n).problem,
            "delivers 512x512, not the requested 4000x3000 (Width 4000 is outside the camera's "
            "1..2048); it can deliver 1..2048 x 1..2048 px");
}

TEST(CameraFormat, APixelFormatOutsideTheAcceptableOnesIsRefused) {
  const CameraFormatRequest want{64, 48, {PixelFormat::kYuyv, PixelFormat::kMjpeg}, 0.0};
  EXPECT_TRUE(judge_format(want, answer(64, 48, PixelFormat::kMjpeg)).ok);
  const FormatVerdict v = judge_format(want, answer(64, 48, PixelFormat::kMono8));
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.problem, "delivers Mono8, not one of YUYV MJPEG");
}

TEST(CameraFormat, AnUnknownSizeOrAnEmptyRequestPasses) {
  EXPECT_TRUE(judge_format({640, 480, {}, 0.0}, answer(0, 0)).ok);
  EXPECT_TRUE(judge_format({}, answer(123, 45)).ok);
}

TEST(CameraFormat, TextNamesSizeFormatAndRate) {
  EXPECT_EQ(format_text({640, 480, PixelFormat::kMono8, 30.0}), "640x480 Mono8 at 30 Hz");
  EXPECT_EQ(format_text({640, 480, PixelFormat::kYuyv, 0.0}), "640x480 YUYV");
  EXPECT_EQ(format_text({}), "size unknown");
  EXPECT_TRUE((CameraFormat{8, 6, PixelFormat::kMono8, 30.0})
                  .same_image({8, 6, PixelFormat::kMono8, 60.0}));
  EXPECT_FALSE(
      (CameraFormat{8, 6, PixelFormat::kMono8, 30.0}).same_image({8, 6, PixelFormat::kRgb8, 30.0}));
}

TEST(CameraFormat, TheNewStateAndTheEventsHaveNames) {
  EXPECT_EQ(to_string(SourceState::kFormatMismatch), "format-mismatch");
  EXPECT_EQ(to_string(FormatEventKind::kLost), "format lost");
  EXPECT_EQ(to_string(FormatEventKind::kRestored), "format restored");
  EXPECT_EQ(to_string(FormatEventCause::kSourceChange), "source change");
}

}  // namespace
}  // namespace hd::drivers
