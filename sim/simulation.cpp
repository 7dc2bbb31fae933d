#include "sim/simulation.h"

#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "sim/frame_timing_model.h"
#include "sim/head_motion.h"
#include "sim/primitive_meshes.h"
#include "sim/sim_camera_renderer.h"
#include "sim/sim_epoch.h"
#include "sim/tracker_effects.h"

namespace hd::sim {

Simulation::Simulation(Scene scene)
    : scene_(std::move(scene)), epoch_(std::make_shared<SimEpoch>()) {
  if (scene_.cameras.empty()) throw std::invalid_argument(scene_.file + ": a scene needs a camera");
  model_.background_rgb = scene_.background_rgb;
  for (const ScenePrimitive& p : scene_.geometry) {
    for (render::TexturedMesh& m : primitive_meshes(p, scene_.file))
      model_.meshes.push_back(std::move(m));
  }
  for (const SceneObject& o : scene_.objects) {
    const std::size_t first = model_.meshes.size();
    for (render::TexturedMesh& m : primitive_meshes(o.shape, scene_.file)) {
      object_local_vertices_.push_back(m.positions_m);
      model_.meshes.push_back(std::move(m));
    }
    object_meshes_.emplace_back(first, model_.meshes.size());
  }
  place_objects(model_, 0.0);
  model_.revision = 1;

  auto epoch = epoch_;
  const auto epoch_hook = [epoch] { return epoch->claim(drivers::monotonic_now_ns()); };
  for (std::size_t i = 0; i < scene_.cameras.size(); ++i) {
    const SceneCamera& c = scene_.cameras[i];
    device_renderers_.push_back(std::make_unique<SimCameraRenderer>(*this, i));
    drivers::MockCameraConfig cc;
    cc.id = "sim:" + c.name;
    cc.width = c.p_c.width;
    cc.height = c.p_c.height;
    cc.rate_hz = c.rate_hz;
    SimCameraRenderer* r = device_renderers_.back().get();
    cc.generator = [r, epoch](drivers::Frame& f, uint64_t) {
      r->render(f, static_cast<double>(f.host_timestamp_ns - epoch->get()) * 1e-9);
    };
    cc.epoch_ns = epoch_hook;
    const SceneEffects& fx = scene_.effects;
    if (fx.camera_delay || fx.network_delay || fx.dropped_frames) {
      auto timing = std::make_shared<FrameTimingModel>(fx, c.rate_hz, i);
      if (timing->has_delay())
        cc.extra_delay_ns = [timing](uint64_t s) { return timing->delay_ns(s); };
      if (timing->has_drops()) cc.drop = [timing](uint64_t s) { return timing->dropped(s); };
    }
    cameras_.push_back(std::make_unique<drivers::MockCamera>(std::move(cc)));
  }
  offline_renderers_.resize(scene_.cameras.size());

  drivers::MockPoseSourceConfig pc;
  pc.id = "sim:head";
  pc.motion = [once = make_head_motion(scene_.head), scene = &scene_](double t_s) {
    return once(motion_time_s(*scene, t_s));  // the one loop rule, as for the objects
  };
  pc.rate_hz = scene_.head.rate_hz;
  pc.epoch_ns = epoch_hook;
  const auto tracker = std::make_shared<TrackerEffects>(scene_.effects);
  if (!tracker->empty()) {
    pc.sample_filter = [tracker](drivers::PoseSample& s, double t_s) { tracker->apply(s, t_s); };
  }
  head_ = std::make_unique<drivers::MockPoseSource>(std::move(pc));
}

Simulation::~Simulation() {
  stop();
}

void Simulation::start() {
  epoch_->claim(drivers::monotonic_now_ns());
  for (auto& c : cameras_) c->start();
  head_->start();
}

void Simulation::stop() {
  if (head_) head_->stop();
  for (auto& c : cameras_) c->stop();
}

std::vector<drivers::CalibratedCamera> Simulation::station_cameras() {
  std::vector<drivers::CalibratedCamera> out;
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    const SceneCamera& c = scene_.cameras[i];
    drivers::CalibratedCamera sc;
    sc.source = cameras_[i].get();
    sc.p_c = c.p_c;
    if (!scene_.effects.lens_distortion) {
      // Frames are ideal pinhole renders: nothing for the station to undistort.
      sc.p_c.distortion = {};
      sc.p_c.distortion_count = 0;
    }
    sc.T_world_real = c.T_world_cam;
    sc.d_m = c.d_m;
    out.push_back(sc);
  }
  return out;
}

render::SyntheticScene Simulation::static_model() const {
  render::SyntheticScene s;
  s.background_rgb = model_.background_rgb;
  s.revision = model_.revision;
  const std::size_t n = object_meshes_.empty() ? model_.meshes.size() : object_meshes_[0].first;
  s.meshes.assign(model_.meshes.begin(), model_.meshes.begin() + static_cast<std::ptrdiff_t>(n));
  return s;
}

void Simulation::place_objects(render::SyntheticScene& model, double t_s) const {
  std::size_t local = 0;
  for (std::size_t o = 0; o < object_meshes_.size(); ++o) {
    const core::Pose pose = object_pose_at(scene_, o, t_s);
    const Eigen::Matrix3f R = pose.R.cast<float>();
    const Eigen::Vector3f t = pose.t.cast<float>();
    for (std::size_t m = object_meshes_[o].first; m < object_meshes_[o].second; ++m, ++local) {
      if (m >= model.meshes.size()) return;  // not a copy of model(): leave it alone
      auto& dst = model.meshes[m].positions_m;
      const auto& src = object_local_vertices_[local];
      for (std::size_t v = 0; v < src.size() && v < dst.size(); ++v) dst[v] = R * src[v] + t;
    }
  }
  ++model.revision;
}

int64_t Simulation::epoch_ns() const {
  return epoch_->get();
}

bool Simulation::set_epoch_ns(int64_t host_ns) {
  return epoch_->claim(host_ns) == host_ns;
}

double Simulation::scene_time_s(int64_t host_ns) const {
  return static_cast<double>(host_ns - epoch_->get()) * 1e-9;
}

SimFrameTiming Simulation::frame_timing(std::size_t camera, uint64_t sequence) const {
  return FrameTimingModel(scene_.effects, scene_.cameras.at(camera).rate_hz, camera).at(sequence);
}

void Simulation::render_frame(std::size_t camera, uint64_t sequence, drivers::Frame& frame) {
  auto& r = offline_renderers_.at(camera);
  if (!r) r = std::make_unique<SimCameraRenderer>(*this, camera);
  const SimFrameTiming t = frame_timing(camera, sequence);
  frame.sequence = sequence;
  frame.host_timestamp_ns = t.exposure_offset_ns;
  frame.device_timestamp_ns = t.exposure_offset_ns;
  frame.device_time_trusted = true;
  r->render(frame, static_cast<double>(t.exposure_offset_ns) * 1e-9);
}

drivers::PoseSample Simulation::head_sample(double t_s, uint64_t sequence) const {
  drivers::PoseSample s = head_->sample_at(t_s);
  s.sequence = sequence;
  const TrackerEffects tracker(scene_.effects);
  if (!tracker.empty()) tracker.apply(s, t_s);
  return s;
}

}  // namespace hd::sim
