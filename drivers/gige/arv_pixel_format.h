#pragma once
// The pixel formats GigeCamera converts, as Aravis (GenICam PFNC) pixel format codes and back.

#include <arv.h>

#include "drivers/frame.h"

namespace hd::drivers {

/// The GenICam code for `f` (Mono8, RGB8 packed, the four 8-bit Bayer layouts); false for a
/// format this driver does not convert (RGBA8, YUYV, MJPEG...), leaving `out` as it was.
bool arv_format_for(PixelFormat f, ArvPixelFormat& out);

/// The inverse of arv_format_for(): which of our formats a camera's code is; false for any other
/// code (Mono12, YUV422...), leaving `out` as it was.
bool pixel_format_of(ArvPixelFormat arv, PixelFormat& out);

/// Whether arv_format_for() knows `f`: GigeCamera can ask a camera for it and convert its frames.
bool gige_converts(PixelFormat f);

}  // namespace hd::drivers
