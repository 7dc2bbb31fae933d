#pragma once
// station.yaml: the real station's devices and parameters (format: docs/station.md).

#include <optional>
#include <string>
#include <vector>

#include "core/config/config_error.h"
#include "core/marking.h"
#include "core/pinhole.h"
#include "core/pose.h"
#include "core/transition.h"
#include "core/workspace_box.h"
#include "drivers/camera_description.h"
#include "render/lens/hmd_profile.h"
#include "sim/scene/scene.h"

namespace hd::station {

/// One camera: the driver id (as hybrid-calib's camera factory takes it: /dev/videoN, a GigE id,
/// mock[:WxH]), its calibration from hybrid-calib (p_c with distortion, and P_c unless `pose`
/// overrides it) and the plane distance d.
/// A camera of station.yaml: the record a scene's camera is too (drivers/camera_description.h).
/// name is "camera<i>" when not given; calibration_file is resolved against the config file's
/// directory, and "" only for an rtp:// camera: p_c and P_c then come from the stream (p_c not
/// valid, R zero, until the first calibration arrives); T_world_cam from the calibration file or
/// `pose:`.
using CameraConfig = drivers::CameraDescription;

/// The head tracker: "mock" (a simulated Android head tracker behind the real HID parser),
/// "hid" (the first head tracker hidapi finds), a hidraw path (/dev/hidrawN) or a USB id
/// VID:PID in hex as lsusb prints it.
struct TrackerConfig {
  std::string id = "hid";
  bool optional = false;  ///< without a tracker the head stays at the home pose
  int line = 0;
};

/// Where the picture goes: a window (or fullscreen on monitor N, e.g. the HMD) with one eye
/// (monitor) or two (HMD).
struct DisplayConfig {
  int monitor = -1;  ///< >= 0 with fullscreen: that monitor
  bool fullscreen = false;
  bool stereo = true;
  double ipd_m = 0.064;
  core::Pinhole eye = core::Pinhole::centred(0.9 * 480, 480, 400);  ///< p_o per eye
  double rate_hz = 90.0;
  double scanout_ms = 2.0;
  /// `hmd:` a shipped profile's name, a profile file, or an inline profile (docs/hmd.md). A
  /// non-neutral profile sets the eyes (size, p_o) and the panel; none / neutral: as above.
  render::lens::HmdProfile hmd = render::lens::HmdProfile::make_neutral();
};

struct ModelConfig {
  std::string scene_file;  ///< a scene file whose geometry is the a-priori model ("" = none)
  double refresh_period_s = 1.0;
  /// Camera pairs (by camera `name`) the model updater reconstructs at the refresh period; with
  /// any, the a-priori model is the scene file's static geometry only (docs/reconstruction.md).
  std::vector<sim::SceneStereoPair> stereo;
};

struct StationConfig {
  std::string file;
  std::vector<CameraConfig> cameras;
  TrackerConfig tracker;
  DisplayConfig display;
  core::TransitionParams transition;
  core::MarkingParams marking;
  core::WorkspaceBox workspace;
  core::Pose T_world_tracker;  ///< tracker frame -> workspace
  core::Pose T_world_home;     ///< where the re-centre key puts the head
  ModelConfig model;
  std::string predictor = "kalman";  ///< none | cv | kalman
};

/// Reads and checks `path`. Any mistake -- YAML syntax, a missing or unknown key, a wrong type,
/// an out-of-range value, a bad enum, a missing or unreadable calibration file -- throws
/// config::ConfigError naming the file, the line and the field.
StationConfig load_station_config(const std::string& path);

/// The same from text; `name` stands for the file in messages, relative paths resolve against
/// its directory.
StationConfig parse_station_config(const std::string& text, const std::string& name);

/// Enum spellings (the same in station.yaml and on the command line).
const std::vector<std::string>& transition_mode_names();  ///< abrupt, global_blend, per_pixel
const std::vector<std::string>& marking_style_names();    ///< none, frame, desaturate, checker
const char* transition_mode_name(core::TransitionMode mode);
const char* marking_style_name(core::MarkingStyle style);

}  // namespace hd::station
