// Region of interest against a GigE camera's Width/Height bounds and increments, and the offset
// asked for when the configuration keeps the camera's own.
#include "drivers/gige/region_fit.h"

#include <gtest/gtest.h>

namespace hd::drivers {

// Widths 16..1024 in steps of 4, heights 16..768 in steps of 2.
constexpr RegionLimits kLimits{16, 1024, 16, 768, 4, 2};

TEST(RegionFit, LimitsTextNamesBoundsAndStepsAboveOne) {
  EXPECT_EQ(limits_text(kLimits), "16..1024 x 16..768 px in steps of 4x2");
  EXPECT_EQ(limits_text(RegionLimits{1, 640, 1, 480, 1, 1}), "1..640 x 1..480 px");
}

TEST(RegionFit, ASizeOnTheGridWithinBoundsFits) {
  EXPECT_EQ(region_size_refusal(kLimits, 640, 480), "");
  EXPECT_EQ(region_size_refusal(kLimits, 16, 16), "");
  EXPECT_EQ(region_size_refusal(kLimits, 1024, 768), "");
}

TEST(RegionFit, ASizeOutsideTheBoundsSaysWhichAndTheBounds) {
  EXPECT_EQ(region_size_refusal(kLimits, 2000, 480), "Width 2000 is outside the camera's 16..1024");
  EXPECT_EQ(region_size_refusal(kLimits, 640, 8), "Height 8 is outside the camera's 16..768");
}

TEST(RegionFit, ASizeOffTheGridSaysTheStepAndBothAxesAreJoined) {
  // 642 - 16 = 626 is not a multiple of 4; 481 - 16 = 465 not one of 2.
  EXPECT_EQ(region_size_refusal(kLimits, 642, 480), "Width 642 is not 16 + a multiple of 4");
  EXPECT_EQ(region_size_refusal(kLimits, 642, 481),
            "Width 642 is not 16 + a multiple of 4, Height 481 is not 16 + a multiple of 2");
}

TEST(RegionFit, AnExplicitOffsetIsAskedForAsIs) {
  EXPECT_EQ(region_offset_to_ask(8, 100, 512, 1024), 8);
  EXPECT_EQ(region_offset_to_ask(0, 100, 512, 1024), 0);
}

TEST(RegionFit, ANegativeOffsetKeepsTheCamerasWhereTheRegionStillFits) {
  EXPECT_EQ(region_offset_to_ask(-1, 100, 512, 1024), 100);  // 100 + 512 <= 1024
  EXPECT_EQ(region_offset_to_ask(-1, 512, 512, 1024), 512);  // exactly to the sensor's edge
  EXPECT_EQ(region_offset_to_ask(-1, 600, 512, 1024), 0);    // 1112 would leave the sensor
  EXPECT_EQ(region_offset_to_ask(-1, 600, 512, 0), 600);     // sensor size unknown: keep it
}

}  // namespace hd::drivers
