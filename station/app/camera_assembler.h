#pragma once
// The one place a camera description (drivers/camera_description.h) becomes a station camera:
// device opened, size negotiated, pipeline built, calibrated camera and link taken, and its line
// in the start report. Scene runs and station.yaml runs both come through here; what differs
// between them is data in CameraAssemblyContext.

#include <functional>
#include <optional>
#include <string>

#include "drivers/camera_description.h"
#include "station/app/startup_report.h"
#include "station/app/station_camera.h"

namespace hd::station {

struct CameraAssemblyContext {
  /// A scene run's simulated device for a "sim:" id (the simulation owns it; nullptr: none). A
  /// station.yaml run has none, and a "sim:" id there is refused.
  std::function<drivers::CameraSource*(const std::string& id)> simulated;
  /// What every frame's age has gained before it leaves the site (a scene's camera and network
  /// delay effects), added to the default bound on its age.
  double known_delay_s = 0.0;
  /// How often the pipeline hands a frame to the model updater; 0 every frame (stereo pairs
  /// need both frames of one exposure: docs/reconstruction.md).
  double model_period_s = 1.0;
  /// The loop waits for a network camera's first frame before its own first frame (a scene run
  /// with --cameras-from: the remote site starts with the station). station.yaml's cameras run
  /// on their own, so a frame without their video is honestly synthetic.
  bool await_network_cameras = false;
  /// --video-view: every camera's video view, replacing the one its file gives.
  std::optional<core::VideoView> video_view;
};

/// Opens `d`'s device (rtp:// ids as a network camera with its key and clock, "sim:" ids from
/// the context, anything else through the driver factory), asks it for the calibrated size and
/// builds its pipeline. `name` is the camera's name in reports; `label` its entry in the start
/// report. On failure (cannot open, or it cannot deliver its calibrated size) the report says why
/// (fatal unless d.optional) and nothing is returned.
std::optional<StationCamera> assemble_camera(const drivers::CameraDescription& d, std::string name,
                                             const std::string& label,
                                             const CameraAssemblyContext& context,
                                             StartupReport& report);

}  // namespace hd::station
