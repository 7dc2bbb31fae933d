// GenICam feature access for GigeCamera: pixel format, binning, region and rate, set and read
// back.
#include "drivers/gige/gige_feature_setup.h"

#include <algorithm>
#include <string_view>

#include "drivers/camera_source.h"
#include "drivers/gige/arv_pixel_format.h"
#include "drivers/gige/region_fit.h"
#include "drivers/gobject_ptr.h"

namespace hd::drivers {

GigeFeatureAnswer configure_gige_features(ArvCamera* cam, const GigeConfig& config,
                                          const std::vector<PixelFormat>& candidates) {
  const std::string& id = config.device_id;
  GErrorHolder error;
  const auto fail = [&](std::string_view what) {
    throw DeviceError("GigE camera '" + id + "': " + std::string(what) + ": " + error.message());
  };
  GigeFeatureAnswer a;
  const auto refuse = [&a](const std::string& what) {
    a.refused += (a.refused.empty() ? "" : "; ") + what;
  };

  // Pixel format: the first acceptable one the camera offers and takes.
  guint n_offered = 0;
  gint64* offered = arv_camera_dup_available_pixel_formats(cam, &n_offered, error.out());
  error.clear();
  bool format_set = false;
  PixelFormat pixel_format = PixelFormat::kMono8;
  std::string format_why;
  for (PixelFormat f : candidates) {
    ArvPixelFormat arv = 0;
    if (!arv_format_for(f, arv)) continue;
    if (offered != nullptr &&
        std::find(offered, offered + n_offered, gint64{arv}) == offered + n_offered) {
      format_why += " " + std::string(to_string(f)) + " (not offered)";
      continue;
    }
    arv_camera_set_pixel_format(cam, arv, error.out());
    const bool took = !error && arv_camera_get_pixel_format(cam, error.out()) == arv && !error;
    if (took) {
      a.arv_format = arv;
      pixel_format = f;
      format_set = true;
      break;
    }
    format_why += " " + std::string(to_string(f)) + " (" + error.message() + ")";
  }
  g_free(offered);
  if (!format_set) {
    throw DeviceError("GigE camera '" + id +
                      "': takes none of the pixel formats asked for:" + format_why);
  }

  // Binning first: the region's sizes are binned pixels.
  if (config.binning_x > 0 || config.binning_y > 0) {
    const gboolean has_binning = arv_camera_is_binning_available(cam, error.out());
    if (error || !has_binning) {
      if (config.binning_x > 1 || config.binning_y > 1)
        refuse("binning " + std::to_string(config.binning_x) + "x" +
               std::to_string(config.binning_y) + ": the camera has no binning");
    } else {
      arv_camera_set_binning(cam, config.binning_x > 0 ? config.binning_x : -1,
                             config.binning_y > 0 ? config.binning_y : -1, error.out());
      if (error) refuse("binning: " + std::string(error.message()));
    }
  }
  if (arv_camera_is_binning_available(cam, error.out()) && !error) {
    gint bx = 1, by = 1;
    arv_camera_get_binning(cam, &bx, &by, error.out());
    if (!error) {
      a.binning_x = bx;
      a.binning_y = by;
    }
  }

  gint x = 0, y = 0, w = 0, h = 0;
  arv_camera_get_region(cam, &x, &y, &w, &h, error.out());
  if (error) fail("reading region of interest");
  RegionLimits limits;
  arv_camera_get_width_bounds(cam, &limits.width_min_px, &limits.width_max_px, error.out());
  if (!error) {
    arv_camera_get_height_bounds(cam, &limits.height_min_px, &limits.height_max_px, error.out());
  }
  const bool have_bounds = !error && limits.width_max_px > 0 && limits.height_max_px > 0;
  limits.width_step_px = arv_camera_get_width_increment(cam, error.out());
  if (error || limits.width_step_px < 1) limits.width_step_px = 1;
  limits.height_step_px = arv_camera_get_height_increment(cam, error.out());
  if (error || limits.height_step_px < 1) limits.height_step_px = 1;
  error.clear();
  if (have_bounds) a.limits = limits_text(limits);
  const GigeRoi& roi = config.roi;
  if (roi.width_px > 0 && roi.height_px > 0) {
    gint sensor_w = 0, sensor_h = 0;
    arv_camera_get_sensor_size(cam, &sensor_w, &sensor_h, error.out());
    error.clear();
    const int want_x = region_offset_to_ask(roi.x_px, x, roi.width_px, sensor_w);
    const int want_y = region_offset_to_ask(roi.y_px, y, roi.height_px, sensor_h);
    if (w != roi.width_px || h != roi.height_px || x != want_x || y != want_y) {
      std::string why;
      if (have_bounds) why = region_size_refusal(limits, roi.width_px, roi.height_px);
      if (why.empty()) {
        arv_camera_set_region(cam, want_x, want_y, roi.width_px, roi.height_px, error.out());
        if (error) why = error.message();
      }
      if (!why.empty())
        refuse("region " + size_text(roi.width_px, roi.height_px) + " at (" +
               std::to_string(want_x) + ", " + std::to_string(want_y) + "): " + why);
      arv_camera_get_region(cam, &x, &y, &w, &h, error.out());
      if (error) fail("reading region of interest");
    }
  }
  if (w <= 0 || h <= 0 || w > 65535 || h > 65535) {
    throw DeviceError("GigE camera '" + id + "' reports an invalid image size " +
                      std::to_string(w) + "x" + std::to_string(h));
  }
  if ((pixel_format != PixelFormat::kMono8 && pixel_format != PixelFormat::kRgb8) &&
      (w < 2 || h < 2)) {
    throw DeviceError("GigE camera '" + id + "': a Bayer image needs at least 2x2 pixels");
  }
  a.offset_x_px = x;
  a.offset_y_px = y;
  a.detail = "region at (" + std::to_string(x) + ", " + std::to_string(y) + "), binning " +
             std::to_string(a.binning_x) + "x" + std::to_string(a.binning_y);

  if (config.frame_rate_hz > 0.0) {
    arv_camera_set_frame_rate(cam, config.frame_rate_hz, error.out());
    if (error) fail("setting frame rate " + std::to_string(config.frame_rate_hz) + " Hz");
  }
  const double rate = arv_camera_get_frame_rate(cam, error.out());
  if (error) fail("reading frame rate");
  a.format = CameraFormat{w, h, pixel_format, rate};
  return a;
}

}  // namespace hd::drivers
