// Our pixel formats <-> Aravis's codes: the six GigeCamera converts map both ways, no other does.
#include "drivers/gige/arv_pixel_format.h"

#include <gtest/gtest.h>

namespace hd::drivers {

TEST(ArvPixelFormat, EachConvertedFormatHasItsGenICamCodeAndBack) {
  const struct {
    PixelFormat ours;
    ArvPixelFormat arv;
  } pairs[] = {
      {PixelFormat::kMono8, 0x01080001},       // Mono8
      {PixelFormat::kRgb8, 0x02180014},        // RGB8 (packed)
      {PixelFormat::kBayerRggb8, 0x01080009},  // BayerRG8
      {PixelFormat::kBayerGrbg8, 0x01080008},  // BayerGR8
      {PixelFormat::kBayerGbrg8, 0x0108000A},  // BayerGB8
      {PixelFormat::kBayerBggr8, 0x0108000B},  // BayerBG8
  };
  for (const auto& p : pairs) {
    ArvPixelFormat arv = 0;
    ASSERT_TRUE(arv_format_for(p.ours, arv)) << to_string(p.ours);
    EXPECT_EQ(arv, p.arv) << to_string(p.ours);
    PixelFormat back = PixelFormat::kRgba8;
    ASSERT_TRUE(pixel_format_of(p.arv, back)) << to_string(p.ours);
    EXPECT_EQ(back, p.ours);
    EXPECT_TRUE(gige_converts(p.ours));
  }
}

TEST(ArvPixelFormat, OtherFormatsAreRefusedAndLeaveTheOutputAlone) {
  for (PixelFormat f : {PixelFormat::kRgba8, PixelFormat::kYuyv, PixelFormat::kMjpeg}) {
    ArvPixelFormat arv = 123;
    EXPECT_FALSE(arv_format_for(f, arv)) << to_string(f);
    EXPECT_EQ(arv, 123u);
    EXPECT_FALSE(gige_converts(f));
  }
  PixelFormat out = PixelFormat::kYuyv;
  EXPECT_FALSE(pixel_format_of(ARV_PIXEL_FORMAT_MONO_12, out));
  EXPECT_FALSE(pixel_format_of(ARV_PIXEL_FORMAT_YUV_422_PACKED, out));
  EXPECT_EQ(out, PixelFormat::kYuyv);
}

}  // namespace hd::drivers
