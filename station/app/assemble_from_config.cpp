// assemble_from_config: the real station (station.yaml -> drivers -> pipelines).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "calib/replay_images.h"
#include "core/video_age.h"
#include "drivers/camera_factory.h"
#include "drivers/camera_format.h"
#include "drivers/hid/hid_head_tracker.h"
#include "drivers/hid/hidapi_transport.h"
#include "drivers/mock/mock_head_tracker_transport.h"
#include "drivers/mock/mock_pose_source.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/srtp_key.h"
#include "drivers/usb/usb_id.h"
#include "sim/scene/scene_file.h"

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

// Why a camera that does not deliver its calibrated size is refused, and what to do about it.
std::string format_refusal(const CameraConfig& cc, const drivers::FormatNegotiation& got,
                           const drivers::FormatVerdict& verdict) {
  const std::string calibrated = drivers::size_text(cc.p_c.width, cc.p_c.height);
  const std::string delivered = drivers::size_text(got.delivered.width_px, got.delivered.height_px);
  std::string how;
  switch (drivers::camera_kind(cc.id)) {
    case drivers::CameraKind::kGige:
      how = "set its region (Width, Height, and binning) so that it delivers " + calibrated;
      break;
    case drivers::CameraKind::kV4l2:
      how = "use a camera with a " + calibrated + " mode (v4l2-ctl -d " + cc.id +
            " --list-formats-ext lists them)";
      break;
    case drivers::CameraKind::kMock:
      how = "give it the id mock:" + calibrated;
      break;
    case drivers::CameraKind::kRtp:
      how = "make the sender send " + calibrated;
      break;
    case drivers::CameraKind::kReplay:
      how = "replay pictures of " + calibrated;
      break;
  }
  return "calibrated at " + calibrated + " (" + cc.calibration_file + "), but the camera " +
         verdict.problem + ". Recalibrate it at " + delivered +
         " (hybrid-calib intrinsics and pose with this camera), or " + how;
}

void add_cameras(StationParts& p, const StationConfig& config) {
  for (const CameraConfig& cc : config.cameras) {
    const std::string label = cc.name + " (" + cc.id + ")";
    std::unique_ptr<drivers::CameraSource> device;
    try {
      if (!cc.key_file.empty() || cc.clock_synchronized) {
        std::string why;
        drivers::RtpReceiveConfig rc;
        const auto address = drivers::parse_rtp_uri(cc.id, why);
        if (!address) throw std::invalid_argument("malformed id " + cc.id + ": " + why);
        rc.listen = *address;
        if (!cc.key_file.empty()) rc.srtp_key = drivers::read_srtp_key_file(cc.key_file);
        if (cc.clock_synchronized) {
          rc.clock = drivers::RtpReceiveConfig::Clock::kSynchronized;
          rc.clock_error_ns = static_cast<int64_t>(cc.clock_error_ms * 1e6);
        }
        device = std::make_unique<drivers::RtpCamera>(std::move(rc));
      } else {
        device = drivers::make_camera_source(cc.id, calib::load_replay_images);
      }
    } catch (const std::exception& e) {
      p.report.missing("camera", label, e.what(), cc.optional);
      continue;
    }
    station::CameraPipelineConfig pc;
    pc.p_c = cc.p_c;  // not valid without a file: the stream's, once it arrives
    pc.T_world_cam = cc.T_world_cam;
    pc.compare_depth_m = cc.d_m;
    pc.calibration_from_stream = cc.calibration_file.empty();
    pc.model_period_s = config.model.refresh_period_s;
    // With stereo pairs every camera hands every frame to the model (docs/reconstruction.md).
    if (!config.model.stereo.empty()) pc.model_period_s = 0.0;
    auto pipe = std::make_unique<station::CameraPipeline>(*device, pc);
    // The calibration fixes the size: the device is asked for it and must deliver exactly it
    // (drivers/camera_format.h, judge_format), so no frame is refused later for its size.
    const drivers::CameraFormatRequest want{cc.p_c.width, cc.p_c.height, {}, 0.0};
    drivers::FormatNegotiation got;
    try {
      got = pipe->negotiate(want);
    } catch (const std::exception& e) {
      p.report.missing("camera", label, e.what(), cc.optional);
      continue;
    }
    const drivers::FormatVerdict verdict = drivers::judge_format(want, got);
    if (!verdict.ok) {
      p.report.missing("camera", label, format_refusal(cc, got, verdict), cc.optional);
      continue;
    }
    const Eigen::Vector3d& c = cc.T_world_cam.t;
    const bool from_stream = cc.calibration_file.empty();
    const std::string delivered =
        got.delivered.known() ? drivers::format_text(got.delivered)
        : from_stream         ? "size unknown until the first frame (its calibration's)"
                              : "size unknown until the first frame (" +
                            drivers::size_text(cc.p_c.width, cc.p_c.height) + " expected)";
    std::string calibration;
    if (from_stream)
      calibration =
          ", calibration: from the stream (none yet: not shown until its sender's arrives)";
    else
      calibration = ", calibration: from file " + cc.calibration_file +
                    (drivers::camera_kind(cc.id) == drivers::CameraKind::kRtp
                         ? " (a calibration in the stream replaces it, with a warning when they "
                           "differ by more than 0.5 px)"
                         : "") +
                    fmt(", centre (%.2f, %.2f, %.2f) m", c.x(), c.y(), c.z());
    const double max_age_s = cc.max_video_age_ms > 0.0
                                 ? 1e-3 * cc.max_video_age_ms
                                 : core::default_max_video_age_s(got.delivered.frame_rate_hz);
    p.report.opened("camera", label,
                    delivered + (got.detail.empty() ? "" : " (" + got.detail + ")") + calibration +
                        fmt(", d = %g m", cc.d_m) +
                        (from_stream            ? ""
                         : pipe->undistorting() ? ", undistorted"
                                                : ", no distortion") +
                        fmt(", live while under %.0f ms old", 1e3 * max_age_s) +
                        (cc.max_video_age_ms > 0.0 ? "" : " (3 frame periods, >= 100 ms)"));
    p.cameras.push_back({pipe.get(), cc.p_c, cc.T_world_cam, cc.d_m, max_age_s});
    p.camera_names.push_back(cc.name);
    p.camera_calibration_files.push_back(cc.calibration_file);
    p.devices.push_back(std::move(device));
    p.pipelines.push_back(std::move(pipe));
  }
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
  if (p.pipelines.empty()) {
    p.report.opened("model", config.model.scene_file,
                    fmt("%g meshes, never re-textured (no camera)", p.model.meshes.size()));
    return;
  }
  std::vector<station::ModelCamera> mc;
  for (std::size_t i = 0; i < p.pipelines.size(); ++i)
    mc.push_back({&p.pipelines[i]->model_frames(), p.cameras[i].p_c, p.cameras[i].T_world_real});
  station::ModelUpdaterConfig uc;
  uc.refresh_period_s = config.model.refresh_period_s;
  std::string pairs;
  for (const sim::SceneStereoPair& sp : config.model.stereo) {
    const auto l = std::find(p.camera_names.begin(), p.camera_names.end(), sp.left);
    const auto r = std::find(p.camera_names.begin(), p.camera_names.end(), sp.right);
    if (l == p.camera_names.end() || r == p.camera_names.end()) {
      p.report.missing("stereo pair", sp.left + "+" + sp.right, "a camera of the pair did not open",
                       true);
      continue;
    }
    uc.stereo_pairs.push_back(
        model_stereo_pair(sp, static_cast<std::size_t>(l - p.camera_names.begin()),
                          static_cast<std::size_t>(r - p.camera_names.begin()), config.workspace));
    pairs += (pairs.empty() ? "" : ", ") + sp.left + "+" + sp.right;
  }
  p.updater_clock = std::make_unique<render::MonotonicLoopClock>();
  try {
    p.updater = std::make_unique<station::ModelUpdater>(p.model, mc, uc, *p.updater_clock);
  } catch (const std::exception& e) {  // a pair that cannot be one (RigError names why)
    p.report.missing("stereo pair", "model", e.what(), true);
    uc.stereo_pairs.clear();
    pairs.clear();
    p.updater = std::make_unique<station::ModelUpdater>(p.model, mc, uc, *p.updater_clock);
  }
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
  add_cameras(*p, config);
  add_tracker(*p, config);
  add_model(*p, config);
  p->report.note("config", config.file);
  configure_frame(*p, config.display, config.transition, config.marking, config.workspace,
                  config.predictor, o);
  return p;
}

}  // namespace hd::station
