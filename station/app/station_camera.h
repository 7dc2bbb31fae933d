#pragma once
// One camera of the station, from its description to the summary: the device, the pipeline the
// station reads it through, the calibrated camera it is measured and drawn with, and the network
// link where it has one. StationParts holds one per camera, so nothing keeps indices aligned.

#include <memory>
#include <string>

#include "drivers/calibrated_camera.h"
#include "drivers/camera_description.h"
#include "drivers/camera_link.h"
#include "drivers/camera_source.h"
#include "station/video/camera_pipeline.h"

namespace hd::station {

struct StationCamera {
  drivers::CameraDescription description;  ///< as the scene file or station.yaml gave it
  /// Its name in reports, frames.csv and the summary: station.yaml's name, or a scene's device
  /// id ("sim:<name>", "net:<name>" for the network camera standing in for it).
  std::string name;
  /// Owned device; null when the simulation owns it. Declared before the pipeline, so the
  /// pipeline (its consumer) is destroyed first.
  std::unique_ptr<drivers::CameraSource> device;
  std::unique_ptr<CameraPipeline> pipeline;
  drivers::CalibratedCamera calibrated;  ///< source = the pipeline
  /// The device's network side (view need, link statistics), null for a camera on this host.
  drivers::CameraLink* link = nullptr;
  /// The loop waits for its first frame before the first frame is drawn (a network camera of a
  /// scene run: the remote site may still be starting).
  bool awaited = false;
};

}  // namespace hd::station
