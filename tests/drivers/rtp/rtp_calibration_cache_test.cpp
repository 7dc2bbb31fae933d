// RtpCalibrationCache: calibrations found by revision among the newest four, refusals and size
// mismatches counted, with hand-made calibrations.
#include "drivers/rtp/rtp_calibration_cache.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

StreamCalibration calibration(uint32_t revision, int width = 640, int height = 480) {
  StreamCalibration c;
  c.camera_index = 2;
  c.revision = revision;
  c.p_c = core::Pinhole::centred(500.0 + revision, width, height);
  return c;
}

TEST(RtpCalibrationCache, AFrameFindsItsRevisionAmongTheNewestFour) {
  RtpCalibrationCache cache;
  EXPECT_FALSE(cache.lookup(1).present);
  EXPECT_FALSE(cache.newest().has_value());
  for (uint32_t r = 1; r <= 5; ++r) cache.add(calibration(r));
  EXPECT_FALSE(cache.lookup(1).present);  // the fifth pushed the first out
  for (uint32_t r = 2; r <= 5; ++r) {
    const FrameCalibration c = cache.lookup(r);
    ASSERT_TRUE(c.present) << r;
    EXPECT_EQ(c.revision, r);
    EXPECT_EQ(c.p_c.fx, 500.0 + r);
    EXPECT_EQ(c.p_c.width, 640);
  }
  ASSERT_TRUE(cache.newest().has_value());
  EXPECT_EQ(cache.newest()->revision, 5u);
  EXPECT_EQ(cache.counts().received, 5u);
}

TEST(RtpCalibrationCache, TheSameRevisionAgainReplacesTheNewestWithoutPushingOthersOut) {
  RtpCalibrationCache cache;
  for (uint32_t r = 1; r <= 4; ++r) cache.add(calibration(r));
  for (int i = 0; i < 10; ++i) cache.add(calibration(4));  // every frame carries it
  EXPECT_TRUE(cache.lookup(1).present);
  EXPECT_EQ(cache.counts().received, 14u);
}

TEST(RtpCalibrationCache, RefusalsAreCountedByReason) {
  RtpCalibrationCache cache;
  cache.refuse(CalibrationError::kNotRotation);
  cache.refuse(CalibrationError::kNotRotation);
  cache.refuse(CalibrationError::kBadSize);
  cache.refuse(CalibrationError::kNone);  // nothing refused: nothing counted
  const RtpCalibrationCache::Counts n = cache.counts();
  EXPECT_EQ(n.refused[static_cast<std::size_t>(CalibrationError::kNotRotation)], 2u);
  EXPECT_EQ(n.refused[static_cast<std::size_t>(CalibrationError::kBadSize)], 1u);
  EXPECT_EQ(n.refused[static_cast<std::size_t>(CalibrationError::kNone)], 0u);
  EXPECT_EQ(n.refused_total, 3u);
  EXPECT_EQ(n.received, 0u);
}

TEST(RtpCalibrationCache, AFrameOfAnotherSizeThanItsCalibrationDoesNotFitAndIsCounted) {
  RtpCalibrationCache cache;
  cache.add(calibration(7, 640, 480));
  const FrameCalibration c = cache.lookup(7);
  EXPECT_TRUE(cache.fits(c, 640, 480));
  EXPECT_FALSE(cache.fits(c, 320, 240));
  EXPECT_FALSE(cache.fits(c, 640, 479));
  EXPECT_TRUE(cache.fits(FrameCalibration{}, 320, 240));  // none: the file's applies
  cache.count_published(true);
  cache.count_published(false);
  const RtpCalibrationCache::Counts n = cache.counts();
  EXPECT_EQ(n.size_mismatch, 2u);
  EXPECT_EQ(n.frames_with_calibration, 1u);
}

}  // namespace
}  // namespace hd::drivers
