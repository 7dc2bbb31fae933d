// assemble_from_scene: the simulated station (scene file -> Simulation -> mock devices).
#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "core/video_age.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_uri.h"
#include "sim/scene_epoch.h"
#include "station/app/camera_assembler.h"
#include "station/app/report_text.h"
#include "station/app/station_parts.h"

namespace hd::station {
namespace {

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s.empty() ? "none" : s;
}

}  // namespace

std::unique_ptr<StationParts> assemble_from_scene(sim::Scene scene, const RunOptions& o,
                                                  SceneDevices devices) {
  auto p = std::make_unique<StationParts>();
  p->source_kind = "scene";
  p->source_file = scene.file;
  p->default_seconds = scene.duration_s;

  DisplayConfig display;
  display.eye = core::Pinhole::centred(0.9 * scene.station.eye_width.value_or(480),
                                       scene.station.eye_width.value_or(480),
                                       scene.station.eye_height.value_or(400));
  core::TransitionParams transition;
  if (scene.station.m_t) transition.m_t = *scene.station.m_t;
  if (scene.station.eps) transition.eps = *scene.station.eps;
  core::MarkingParams marking;
  marking.style = core::MarkingStyle::kFrame;  // the variant visible at a glance in the outputs
  const core::WorkspaceBox workspace = scene.workspace;
  const std::vector<std::string> effects = scene.effects.names();
  const std::string scene_name = scene.name;
  const double duration_s = scene.duration_s;
  const bool looped = scene.loop;

  p->simulation = std::make_unique<sim::Simulation>(std::move(scene));
  sim::Simulation& sim = *p->simulation;
  if (!o.scene_epoch.empty()) {
    std::string why;
    const auto epoch_realtime = sim::parse_scene_epoch(o.scene_epoch, why);
    if (!epoch_realtime) throw std::invalid_argument("--scene-epoch: " + why);
    p->scene_epoch_ns = sim::realtime_to_monotonic_ns(*epoch_realtime);
    p->scene_epoch_text = o.scene_epoch;
    sim.set_epoch_ns(p->scene_epoch_ns);  // before any device starts: the head waits for it
  }
  // --cameras-from: camera i arrives as rtp://HOST:(PORT + 2 i) (hybrid-remote --scene).
  std::optional<drivers::RtpAddress> net;
  if (!o.cameras_from.empty()) {
    std::string why;
    net = drivers::parse_rtp_uri(o.cameras_from, why);
    if (!net) throw std::invalid_argument("--cameras-from: " + why);
    p->cameras_from = o.cameras_from;
    p->camera_wait_s = o.camera_wait_s;
  }
  const auto& staleness = sim.model_staleness();
  // What the scene's own effects add to every frame's age: a real site knows its link's delay.
  double known_delay_s = 0.0;
  for (const auto& d : {sim.scene().effects.camera_delay, sim.scene().effects.network_delay})
    if (d) known_delay_s += 1e-3 * (d->mean_ms + 3.0 * d->jitter_ms);

  const bool ground_truth = sim.scene().model.moved_objects == sim::MovedObjects::kGroundTruth;
  const std::vector<sim::SceneStereoPair> stereo =
      ground_truth ? std::vector<sim::SceneStereoPair>{} : sim.scene().stereo;

  // Cameras: each simulated device through the station's pipeline, as a real one would be, or
  // with --cameras-from the network camera hybrid-remote --scene sends it as.
  CameraAssemblyContext ctx;
  if (devices == SceneDevices::kStepped) {
    // Any host time: the run's own clock starts there. Not 0, which means "no frame yet".
    p->stepped = std::make_unique<StationParts::SteppedDevices>();
    p->stepped->epoch_ns = 1'000'000'000;
    for (std::size_t i = 0; i < sim.scene().cameras.size(); ++i)
      p->stepped->cameras.push_back(
          std::make_unique<sim::SteppedCamera>(sim, i, p->stepped->epoch_ns));
    p->stepped->head = std::make_unique<sim::SteppedHead>(sim, p->stepped->epoch_ns);
  }
  ctx.simulated = [&sim,
                   stepped = p->stepped.get()](const std::string& id) -> drivers::CameraSource* {
    for (std::size_t i = 0; i < sim.scene().cameras.size(); ++i)
      if (sim.camera(i).id() == id)
        return stepped ? static_cast<drivers::CameraSource*>(stepped->cameras[i].get())
                       : &sim.camera(i);
    return nullptr;
  };
  ctx.known_delay_s = known_delay_s;
  // With stereo pairs every camera hands every frame to the model: the updater then finds a
  // pair's two frames of one exposure, and every camera's newest frame within a frame time of
  // them, so the textures show the workspace at the instant the geometry was measured (with one
  // frame per period a camera's newest could be a period older, and paint a moving object's
  // colours where the reconstruction has nothing).
  ctx.model_period_s = !stereo.empty() ? 0.0 : staleness ? staleness->period_s : 1.0;
  ctx.await_network_cameras = true;
  ctx.video_view = core::parse_video_view(o.video_view);
  const std::vector<drivers::CalibratedCamera> sim_cams = sim.station_cameras();
  for (std::size_t i = 0; i < sim_cams.size(); ++i) {
    drivers::CameraDescription d = sim.scene().cameras[i];
    d.p_c = sim_cams[i].p_c;  // without the lens_distortion effect: ideal, nothing to undo
    std::string name = d.id;
    if (net) {
      drivers::RtpAddress at = *net;
      at.port = static_cast<uint16_t>(net->port + 2 * i);
      d.id = drivers::to_uri(at);
      name = "net:" + d.name;
      // A shared --scene-epoch already takes the two sites' CLOCK_REALTIME to agree (one host
      // in the demo): capture times are mapped through it too, so a frame's time is its
      // exposure's scene time exactly, not within an RTCP estimate's error.
      if (p->scene_epoch_ns != 0) {
        d.clock_synchronized = true;
        d.clock_error_ms = 0.0;
      }
    }
    if (auto cam = assemble_camera(d, name, name, ctx, p->report))
      p->cameras.push_back(std::move(*cam));
  }

  // Head: the scene's tracker frame is the workspace; re-centre brings the head back to where
  // the scene's motion starts.
  station::AlignedPoseSourceConfig ac;
  ac.alignment.T_world_home = sim.head_sample(0.0, 0).T_tracker_head;
  drivers::PoseSource& head_device =
      p->stepped ? static_cast<drivers::PoseSource&>(*p->stepped->head) : sim.head();
  p->head = std::make_unique<station::AlignedPoseSource>(head_device, ac);
  try {
    p->head->open();
    p->report.opened("tracker", sim.head().id(),
                     fmt("simulated head, %g Hz, ", sim.scene().head.rate_hz) +
                         (sim.scene().head.trajectory_csv.empty()
                              ? fmt("%g scripted keyframes", sim.scene().head.keyframes.size())
                              : "trajectory " + sim.scene().head.trajectory_csv) +
                         "; R re-centres on its start pose");
  } catch (const std::exception& e) {
    p->report.missing("tracker", sim.head().id(), e.what(), false);
  }

  // Model: the scene's static geometry, completed by the stereo pairs' reconstruction (or, for
  // comparisons only, with the moving objects placed from the simulator's ground truth), and
  // re-textured from the cameras with the staleness the scene sets.
  p->model = ground_truth ? sim.model() : sim.static_model();
  if ((staleness || !stereo.empty()) && !p->cameras.empty()) {
    station::ModelUpdaterConfig uc;
    uc.refresh_period_s = staleness ? staleness->period_s : 1.0;
    uc.delay_s = staleness ? staleness->delay_s : 0.0;
    if (ground_truth) {
      uc.move_objects = [&sim](render::SyntheticScene& m, int64_t capture_ns) {
        sim.place_objects(m, sim.scene_time_s(capture_ns));
      };
    }
    const std::string names = add_model_updater(*p, uc, stereo, workspace);
    std::string recon_note = "moved objects: ground truth (comparison only)";
    if (!ground_truth) {
      recon_note = "moved objects: reconstructed by ";
      recon_note += names.empty() ? "no stereo pair (not in the model)" : names;
    }
    p->report.opened("model", "scene geometry",
                     fmt("%g meshes, re-textured from the cameras every %g s with %g s delay; ",
                         p->model.meshes.size(), uc.refresh_period_s, uc.delay_s) +
                         recon_note);
  } else {
    p->report.opened("model", "scene geometry",
                     fmt("%g meshes as the scene defines them (no model_staleness effect: never "
                         "re-textured)",
                         p->model.meshes.size()));
  }

  p->report.note("scene", p->source_file + " (" + scene_name + ", " + fmt("%g s", duration_s) +
                              (looped ? ", motion looped" : "") + ")");
  p->report.note("effects", join(effects));
  if (net)
    p->report.note("cameras", "from the network: camera i on " + net->host + ":" +
                                  std::to_string(net->port) +
                                  " + 2 i (hybrid-remote --scene renders and sends them; their "
                                  "effects are applied there); p_c and P_c from the scene file");
  if (p->scene_epoch_ns != 0)
    p->report.note("scene time", "t = 0 at --scene-epoch " + o.scene_epoch + " (CLOCK_REALTIME), " +
                                     fmt("%+.3f s from now",
                                         1e-9 * static_cast<double>(p->scene_epoch_ns -
                                                                    drivers::monotonic_now_ns())));
  configure_frame(*p, display, transition, marking, workspace, "kalman", o);
  return p;
}

}  // namespace hd::station
