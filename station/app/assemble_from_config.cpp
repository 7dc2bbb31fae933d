// assemble_from_config: the real station (station.yaml -> drivers -> pipelines).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/video_age.h"
#include "drivers/camera_format.h"
#include "drivers/hid/hid_head_tracker.h"
#include "drivers/hid/hidapi_transport.h"
#include "drivers/mock/mock_head_tracker_transport.h"
#include "drivers/mock/mock_pose_source.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/srtp_key.h"
#include "drivers/usb/usb_id.h"
#include "sim/scene/scene_file.h"

#include "station/app/camera_assembler.h"
#include "station/app/report_text.h"
#include "station/app/station_parts.h"

namespace hd::station {
namespace {

// The mock tracker's motion (tracker frame): from the origin 0.6 m to the right while turning
// 25 deg toward the left, and back, every 12 s -- away from a camera at the origin and back.
drivers::TrajectorySample mock_head_motion(double t_s) {
  const double s = 0.5 * (1.0 - std::cos(2.0 * M_PI * t_s / 12.0));
  drivers::TrajectorySample out;
  out.t_s = t_s;
  out.position_m = {0.6 * s, 0.0, 0.0};
  out.q = Eigen::Quaterniond(Eigen::AngleAxisd(25.0 * M_PI / 180.0 * s, -Eigen::Vector3d::UnitY()));
  return out;
}

// The HID opener for a tracker id, or nullptr with `why`.
drivers::HidTransportOpener tracker_opener(const std::string& id, std::string& what,
                                           std::string& why) {
  if (id == "mock") {
    drivers::MockHeadTrackerConfig mc;
    mc.motion = mock_head_motion;
    what =
        "simulated Android head tracker (HID reports through the real parser), scripted "
        "motion 0.6 m sideways and back every 12 s";
    return drivers::mock_head_tracker_opener(mc);
  }
  if (id == "hid") {
    what = "first HID head tracker hidapi finds";
    return drivers::hidapi_opener();
  }
  if (id.rfind("/dev/", 0) == 0) {
    what = "HID head tracker at " + id;
    return drivers::hidapi_opener(id);
  }
  if (auto usb = drivers::parse_usb_id(id)) {
    for (const drivers::HidDeviceEntry& e : drivers::enumerate_hid_devices())
      if (e.vendor_id == usb->vendor_id && e.product_id == usb->product_id) {
        what = "HID head tracker " + id + " at " + e.path + " (" + e.product + ")";
        return drivers::hidapi_opener(e.path);
      }
    why = "no HID device " + id + " is connected (`hybrid-station devices` lists what is there)";
    return {};
  }
  why = "unknown tracker id '" + id + "': expected mock, hid, /dev/hidrawN or VID:PID";
  return {};
}

// A pose source that holds the head at the tracker origin (the tracker is optional and absent).
std::unique_ptr<drivers::PoseSource> still_head() {
  drivers::MockPoseSourceConfig c;
  c.id = "still-head";
  c.rate_hz = 100.0;
  c.motion = [](double t_s) {
    drivers::TrajectorySample s;
    s.t_s = t_s;
    return s;
  };
  return std::make_unique<drivers::MockPoseSource>(c);
}

void add_cameras(StationParts& p, const StationConfig& config, const RunOptions& o) {
  CameraAssemblyContext ctx;
  ctx.video_view = core::parse_video_view(o.video_view);
  ctx.model_period_s = config.model.refresh_period_s;
  // With stereo pairs every camera hands every frame to the model (docs/reconstruction.md).
  if (!config.model.stereo.empty()) ctx.model_period_s = 0.0;
  for (const CameraConfig& cc : config.cameras)
    if (auto cam = assemble_camera(cc, cc.name, cc.name + " (" + cc.id + ")", ctx, p.report))
      p.cameras.push_back(std::move(*cam));
}

void add_tracker(StationParts& p, const StationConfig& config) {
  const TrackerConfig& tc = config.tracker;
  std::string what, why;
  drivers::HidTransportOpener opener = tracker_opener(tc.id, what, why);
  if (opener) {
    drivers::HidHeadTrackerConfig hc;
    hc.id = tc.id;
    hc.opener = std::move(opener);
    auto tracker = std::make_unique<drivers::HidHeadTracker>(std::move(hc));
    try {
      tracker->open();
      p.report.opened("tracker", tc.id, what);
      p.tracker = std::move(tracker);
    } catch (const std::exception& e) {
      why = e.what();
    }
  }
  if (!p.tracker) {
    p.report.missing("tracker", tc.id, why, tc.optional);
    if (!tc.optional) return;
    p.tracker = still_head();
    p.tracker->open();
    p.report.opened("tracker", p.tracker->id(), "head held at the tracker origin (no tracker)");
  }
  station::AlignedPoseSourceConfig ac;
  ac.alignment.T_world_tracker = config.T_world_tracker;
  ac.alignment.T_world_home = config.T_world_home;
  p.head = std::make_unique<station::AlignedPoseSource>(*p.tracker, ac);
}

void add_model(StationParts& p, const StationConfig& config) {
  if (config.model.scene_file.empty()) {
    p.report.opened("model", "none",
                    "no model.scene in the config: the synthetic view shows the background only");
    return;
  }
  // The scene file's geometry is the a-priori model; its simulated devices are never started.
  sim::Simulation geometry(sim::load_scene(config.model.scene_file));
  // With stereo pairs the moving objects get into the model as the pairs see them; without,
  // the scene's objects stand where they are at t = 0.
  p.model = config.model.stereo.empty() ? geometry.model() : geometry.static_model();
  if (p.cameras.empty()) {
    p.report.opened("model", config.model.scene_file,
                    fmt("%g meshes, never re-textured (no camera)", p.model.meshes.size()));
    return;
  }
  station::ModelUpdaterConfig uc;
  uc.refresh_period_s = config.model.refresh_period_s;
  const std::string pairs = add_model_updater(p, uc, config.model.stereo, config.workspace);
  p.report.opened("model", config.model.scene_file,
                  fmt("%g meshes, re-textured from the cameras every %g s", p.model.meshes.size(),
                      uc.refresh_period_s) +
                      (pairs.empty() ? std::string() : "; reconstructed by " + pairs));
}

}  // namespace

std::unique_ptr<StationParts> assemble_from_config(const StationConfig& config,
                                                   const RunOptions& o) {
  auto p = std::make_unique<StationParts>();
  p->source_kind = "config";
  p->source_file = config.file;
  p->default_seconds = o.headless ? 10.0 : 0.0;
  add_cameras(*p, config, o);
  add_tracker(*p, config);
  add_model(*p, config);
  p->report.note("config", config.file);
  configure_frame(*p, config.display, config.transition, config.marking, config.workspace,
                  config.predictor, o);
  return p;
}

}  // namespace hd::station
