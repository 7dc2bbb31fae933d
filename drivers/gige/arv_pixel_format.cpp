// Our pixel formats <-> Aravis's pixel format codes, for the ones GigeCamera converts.
#include "drivers/gige/arv_pixel_format.h"

namespace hd::drivers {

bool arv_format_for(PixelFormat f, ArvPixelFormat& out) {
  switch (f) {
    case PixelFormat::kMono8:
      out = ARV_PIXEL_FORMAT_MONO_8;
      return true;
    case PixelFormat::kRgb8:
      out = ARV_PIXEL_FORMAT_RGB_8_PACKED;
      return true;
    case PixelFormat::kBayerRggb8:
      out = ARV_PIXEL_FORMAT_BAYER_RG_8;
      return true;
    case PixelFormat::kBayerGrbg8:
      out = ARV_PIXEL_FORMAT_BAYER_GR_8;
      return true;
    case PixelFormat::kBayerGbrg8:
      out = ARV_PIXEL_FORMAT_BAYER_GB_8;
      return true;
    case PixelFormat::kBayerBggr8:
      out = ARV_PIXEL_FORMAT_BAYER_BG_8;
      return true;
    default:
      return false;
  }
}

bool pixel_format_of(ArvPixelFormat arv, PixelFormat& out) {
  for (PixelFormat f :
       {PixelFormat::kMono8, PixelFormat::kRgb8, PixelFormat::kBayerRggb8, PixelFormat::kBayerGrbg8,
        PixelFormat::kBayerGbrg8, PixelFormat::kBayerBggr8}) {
    ArvPixelFormat a = 0;
    if (arv_format_for(f, a) && a == arv) {
      out = f;
      return true;
    }
  }
  return false;
}

bool gige_converts(PixelFormat f) {
  ArvPixelFormat unused = 0;
  return arv_format_for(f, unused);
}

}  // namespace hd::drivers
