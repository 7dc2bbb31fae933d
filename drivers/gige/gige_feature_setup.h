#pragma once
// A GigE camera's GenICam features set from a GigeConfig (pixel format, binning, region, frame
// rate) and read back: what the camera delivers, and what it refused and why.

#include <arv.h>

#include <string>
#include <vector>

#include "drivers/camera_format.h"
#include "drivers/gige/gige_config.h"

namespace hd::drivers {

/// The camera's answer to the configuration, every value read back from it.
struct GigeFeatureAnswer {
  CameraFormat format;            ///< size, pixel format (one of the candidates) and rate
  ArvPixelFormat arv_format = 0;  ///< `format.pixel_format` as the camera names it
  int binning_x = 1;              ///< 1 when the camera has no binning
  int binning_y = 1;
  int offset_x_px = 0;  ///< the region's offset on the sensor
  int offset_y_px = 0;
  std::string refused;  ///< what the camera did not take, and why ("" when it took everything)
  std::string limits;   ///< the sizes it can deliver ("" when it does not say)
  std::string detail;   ///< region offset and binning as read back
};

/// Sets, in this order, the first pixel format of `candidates` the camera offers and takes,
/// binning (the region's sizes are binned pixels), the region (only where the camera's Width /
/// Height bounds and increments allow it; a refusal is reported, not thrown) and the frame rate,
/// and reads each back. `cam` is open with Aravis's range check on, so an out-of-range value is
/// refused by Aravis instead of clamped by the camera.
///
/// Throws DeviceError naming `config.device_id` when the camera takes none of the candidates,
/// reports an unusable size, or a feature cannot be read (or the rate set).
GigeFeatureAnswer configure_gige_features(ArvCamera* cam, const GigeConfig& config,
                                          const std::vector<PixelFormat>& candidates);

}  // namespace hd::drivers
