#pragma once
// A simulated workspace as a scene file describes it (scenes/*.yaml, docs/scenes.md): plain values,
// filled by load_scene() and turned into mock devices and a model by sim/Simulation.
//
// World frame: the cameras' axes at the identity pose (x right, y DOWN, z forward), metres. "Up"
// is -y, so a table top at height 0.4 m below the origin is the plane y = +0.4, and yaw turns
// about the vertical (y) axis.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "core/workspace_box.h"
#include "drivers/camera_description.h"

namespace hd::sim {

/// A surface texture: a procedural checker or a PNG file.
struct SceneTexture {
  enum class Kind { kChecker, kImage };
  Kind kind = Kind::kChecker;
  std::array<uint8_t, 3> color0{200, 200, 200};
  std::array<uint8_t, 3> color1{90, 90, 90};
  double cell_m = 0.1;     ///< checker cell edge on the surface
  std::string image_path;  ///< kImage: resolved against the scene file's directory
};

/// A box or a flat rectangle. `size_m` is the box's extent along its own x, y, z (a quad uses x
/// and y: its plane is its local z = 0). Orientation: roll about x, pitch about y', yaw about z''
/// would be ambiguous with y down, so it is given as yaw (about world y), then pitch (about the
/// object's x), then roll (about its z): R = Ry(yaw) * Rx(pitch) * Rz(roll).
struct ScenePrimitive {
  enum class Shape { kBox, kQuad };
  std::string name;
  Shape shape = Shape::kBox;
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Constant(0.1);
  Eigen::Vector3d ypr_deg = Eigen::Vector3d::Zero();  ///< yaw, pitch, roll
  SceneTexture texture;
  int line = 0;  ///< in the scene file, for messages
};

/// Where a moving object is at a time: linear between keyframes, held before the first and after
/// the last.
struct ObjectKeyframe {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_deg = 0.0;  ///< about world y
};

/// A box that moves: the gripper, or a block it carries. The shape's centre_m/ypr are relative to
/// the object's keyframed origin.
struct SceneObject {
  std::string name;
  ScenePrimitive shape;
  std::vector<ObjectKeyframe> keyframes;  ///< at least one, strictly increasing t_s
  /// Carried: from pick_s to place_s the object keeps the offset to `carrier` it had at pick_s;
  /// after place_s it stays where it was put down (its own keyframes before pick_s).
  std::string carrier;  ///< name of another object, "" = not carried
  double pick_s = 0.0;
  double place_s = 0.0;
};

/// A scene's camera: the station's camera description (drivers/camera_description.h), with id
/// "sim:<name>" and rate_hz the simulated rate; the scene reader fills the same record station.yaml
/// gives.
using SceneCamera = drivers::CameraDescription;

/// The operator's head (tracker frame = world frame): a CSV trajectory or scripted keyframes.
struct HeadKeyframe {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d ypr_deg = Eigen::Vector3d::Zero();  ///< as ScenePrimitive
};
struct SceneHead {
  std::string trajectory_csv;  ///< resolved path, or "" for keyframes
  std::vector<HeadKeyframe> keyframes;
  double rate_hz = 500.0;
  bool smooth = true;  ///< keyframes: ease in/out (raised cosine) instead of linear
};

// ---- effects: each present only when the scene lists it ----
struct SensorNoiseEffect {
  double sigma_dn = 2.0;  ///< gaussian, per channel, in digital numbers (0..255)
  uint64_t seed = 1;
};
struct ExposureEffect {
  double gain = 1.0;  ///< out = gain * in + offset, clipped to 0..255
  double offset_dn = 0.0;
};
struct LensDistortionEffect {};  ///< distorts frames with each camera's own coefficients
struct MotionBlurEffect {
  double exposure_ms = 10.0;  ///< the shutter is open [t, t + exposure]
  int samples = 4;            ///< renders averaged across it
};
struct RollingShutterEffect {
  double readout_ms = 20.0;  ///< first to last row; row r is exposed at t + r * readout / height
  int bands = 16;            ///< rows rendered per time step = height / bands
};
struct DroppedFramesEffect {
  double probability = 0.05;
  uint64_t seed = 2;
};
struct DelayEffect {
  double mean_ms = 0.0;
  double jitter_ms = 0.0;  ///< standard deviation (gaussian, truncated at 0 total delay)
  uint64_t seed = 3;
};
struct TrackerNoiseEffect {
  double position_sigma_m = 0.001;
  double orientation_sigma_deg = 0.1;
  uint64_t seed = 4;
};
struct TrackerDriftEffect {
  double position_m_s = 0.001;
  double orientation_deg_s = 0.05;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< unit
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();       ///< unit
};
struct ModelStalenessEffect {
  double period_s = 1.0;  ///< the model is refreshed from camera frames this often
  double delay_s = 0.2;   ///< and a refresh shows the workspace as it was this long before
};

struct SceneEffects {
  std::optional<SensorNoiseEffect> sensor_noise;
  std::optional<ExposureEffect> exposure;
  std::optional<LensDistortionEffect> lens_distortion;
  std::optional<MotionBlurEffect> motion_blur;
  std::optional<RollingShutterEffect> rolling_shutter;
  std::optional<DroppedFramesEffect> dropped_frames;
  std::optional<DelayEffect> camera_delay;
  std::optional<DelayEffect> network_delay;
  std::optional<TrackerNoiseEffect> tracker_noise;
  std::optional<TrackerDriftEffect> tracker_drift;
  std::optional<ModelStalenessEffect> model_staleness;

  bool empty() const;
  /// Names of the listed effects in scene-file spelling ("sensor_noise", ...).
  std::vector<std::string> names() const;
};

/// Two cameras the model updater reconstructs the workspace from (docs/reconstruction.md): the
/// left camera's pixels index the depth mesh; disparities d = x_left - x_right in rectified
/// pixels, accepted in [min_disparity_px, min_disparity_px + num_disparities_px).
struct SceneStereoPair {
  std::string left;  ///< camera names (SceneCamera::name)
  std::string right;
  int min_disparity_px = 8;
  int num_disparities_px = 64;
  std::string matcher = "sgbm-scaled";  ///< "sgbm-scaled", "sgbm" or "bm" (recon::MatcherKind)
  /// The pair is reconstructed at every `every_updates`-th model update (the model's rate / n).
  int every_updates = 1;
  int line = 0;  ///< in the scene file, for messages
};

/// How the station's model learns where moved objects are.
/// kReconstructed (default): the model holds the static geometry only; the stereo pairs'
/// reconstruction adds what is not in it (nothing, without a pair). kGroundTruth: the
/// simulator places the moving objects in the model at the frames' capture time (for
/// comparisons only: no real station knows this).
enum class MovedObjects { kReconstructed, kGroundTruth };

struct SceneModelOptions {
  MovedObjects moved_objects = MovedObjects::kReconstructed;
};

/// Station parameters the scene suggests (the station config or command line may override).
struct SceneStationHints {
  std::optional<double> m_t;
  std::optional<double> eps;
  std::optional<int> eye_width;
  std::optional<int> eye_height;
};

struct Scene {
  std::string file;  ///< where it was read from
  std::string name;
  double duration_s = 20.0;
  /// The head and the moving objects start over every duration_s (a soak outlasts the scene).
  /// Only motion wraps: the scene clock itself, and so tracker drift and delays, runs on.
  bool loop = false;
  core::WorkspaceBox workspace;
  std::array<uint8_t, 3> background_rgb{30, 32, 40};
  std::vector<ScenePrimitive> geometry;  ///< static, a-priori known
  std::vector<SceneObject> objects;      ///< moving (pick-and-place)
  std::vector<SceneCamera> cameras;
  SceneHead head;
  SceneEffects effects;
  std::vector<SceneStereoPair> stereo;
  SceneModelOptions model;
  SceneStationHints station;
};

/// R = Ry(yaw) * Rx(pitch) * Rz(roll), angles in degrees (the scene files' orientation).
Eigen::Matrix3d rotation_from_ypr_deg(const Eigen::Vector3d& ypr_deg);

/// Scene time t_s as the scripted motion sees it: t_s itself, or t_s modulo duration_s when the
/// scene loops (t < 0 is left alone: before the start everything holds its first pose).
double motion_time_s(const Scene& scene, double t_s);

/// The pose of a moving object at time t (keyframes interpolated, carrying applied, looped as
/// motion_time_s says). `index` into scene.objects. Position is the object's origin; R its yaw.
core::Pose object_pose_at(const Scene& scene, std::size_t index, double t_s);

}  // namespace hd::sim
