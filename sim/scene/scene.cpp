#include "sim/scene/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hd::sim {

namespace {

constexpr double kDeg = M_PI / 180.0;

core::Pose keyframe_pose(const std::vector<ObjectKeyframe>& keys, double t_s) {
  auto pose_of = [](const Eigen::Vector3d& p, double yaw_deg) {
    core::Pose out;
    out.R = Eigen::AngleAxisd(yaw_deg * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix();
    out.t = p;
    return out;
  };
  if (keys.empty()) return core::Pose::identity();
  if (t_s <= keys.front().t_s) return pose_of(keys.front().position_m, keys.front().yaw_deg);
  if (t_s >= keys.back().t_s) return pose_of(keys.back().position_m, keys.back().yaw_deg);
  const auto next = std::upper_bound(keys.begin(), keys.end(), t_s,
                                     [](double t, const ObjectKeyframe& k) { return t < k.t_s; });
  const ObjectKeyframe& b = *next;
  const ObjectKeyframe& a = *(next - 1);
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  return pose_of(a.position_m + u * (b.position_m - a.position_m),
                 a.yaw_deg + u * (b.yaw_deg - a.yaw_deg));
}

}  // namespace

bool SceneEffects::empty() const {
  return names().empty();
}

std::vector<std::string> SceneEffects::names() const {
  std::vector<std::string> n;
  if (sensor_noise) n.emplace_back("sensor_noise");
  if (exposure) n.emplace_back("exposure");
  if (lens_distortion) n.emplace_back("lens_distortion");
  if (motion_blur) n.emplace_back("motion_blur");
  if (rolling_shutter) n.emplace_back("rolling_shutter");
  if (dropped_frames) n.emplace_back("dropped_frames");
  if (camera_delay) n.emplace_back("camera_delay");
  if (network_delay) n.emplace_back("network_delay");
  if (tracker_noise) n.emplace_back("tracker_noise");
  if (tracker_drift) n.emplace_back("tracker_drift");
  if (model_staleness) n.emplace_back("model_staleness");
  return n;
}

Eigen::Matrix3d rotation_from_ypr_deg(const Eigen::Vector3d& ypr_deg) {
  return (Eigen::AngleAxisd(ypr_deg.x() * kDeg, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(ypr_deg.y() * kDeg, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(ypr_deg.z() * kDeg, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

double motion_time_s(const Scene& scene, double t_s) {
  if (!scene.loop || !(scene.duration_s > 0.0) || t_s < scene.duration_s) return t_s;
  return std::fmod(t_s, scene.duration_s);
}

core::Pose object_pose_at(const Scene& scene, std::size_t index, double t_scene_s) {
  const double t_s = motion_time_s(scene, t_scene_s);
  const SceneObject& o = scene.objects.at(index);
  if (o.carrier.empty()) return keyframe_pose(o.keyframes, t_s);
  const auto carrier = std::find_if(scene.objects.begin(), scene.objects.end(),
                                    [&](const SceneObject& c) { return c.name == o.carrier; });
  if (carrier == scene.objects.end() || t_s <= o.pick_s) return keyframe_pose(o.keyframes, t_s);
  // The grip: the object's pose in the carrier's frame at the moment it is picked up.
  const core::Pose grip =
      keyframe_pose(carrier->keyframes, o.pick_s).inverse() * keyframe_pose(o.keyframes, o.pick_s);
  return keyframe_pose(carrier->keyframes, std::min(t_s, o.place_s)) * grip;
}

}  // namespace hd::sim
