#pragma once
// One camera as a scene file or station.yaml describes it: which device, its calibration and
// pose, and how the station treats its video. Both readers produce this record and one assembler
// (station/app/camera_assembler.h) turns it into a station camera, so a field added here reaches
// simulated and real runs alike.
//
// Units: metres, milliseconds where the name says so; T_world_cam maps camera to world
// coordinates (DESIGN.md's conventions).

#include <string>

#include "core/pinhole.h"
#include "core/pose.h"
#include "core/video_view.h"

namespace hd::drivers {

struct CameraDescription {
  std::string name;  ///< for reports; a scene's device id is "sim:<name>"
  /// The driver id (drivers/camera_factory.h: v4l2:…, gige:…, rtp://…, mock:…), or "sim:<name>"
  /// for a scene's simulated camera.
  std::string id;
  /// Where p_c and T_world_cam were read from ("" when given inline in a scene, or for an rtp://
  /// camera whose sender streams them: p_c is then not valid until the first one arrives).
  std::string calibration_file;
  core::Pinhole p_c;  ///< with the lens's distortion coefficients
  core::Pose T_world_cam;
  /// A simulated camera's frame rate (scenes: 30 when not given); 0 unknown: a device reports
  /// its own when asked.
  double rate_hz = 0.0;
  double d_m = 1.0;  ///< the plane distance the station projects this camera's video on
  /// How its video is laid into the eye's picture (`video_view`: plane, the default;
  /// fitted-plane; model-depth). d_m is the fitted plane's starting point.
  core::VideoView video_view = core::VideoView::kPlane;
  /// Video older than this at the display time is not shown as live (core/video_age.h);
  /// 0: the default, core::default_max_video_age_s of the rate it delivers plus known delays.
  double max_video_age_ms = 0.0;
  bool optional = false;  ///< a camera that cannot be opened is skipped instead of fatal
  /// A network camera's pre-shared SRTP key file (resolved; "" = no encryption). Its stream
  /// must then be SRTP with this key; anything else is rejected and counted.
  std::string key_file;
  /// A network camera's clocks: false (`clock: measured`, the default) maps the sender's capture
  /// times through the offset measured from its RTCP sender reports and round trip; true
  /// (`clock: synchronized`, sites with chrony/PTP, or one host) through this host's
  /// CLOCK_REALTIME, with `clock_error_ms` as the uncertainty.
  bool clock_synchronized = false;
  double clock_error_ms = 1.0;
  int line = 0;  ///< where it is in its file, for messages (0 unknown)
};

}  // namespace hd::drivers
