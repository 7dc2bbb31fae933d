// Scene files: the shipped scenes load with the values they spell, and each kind of mistake is
// reported with the file, line and field where it is.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "sim/primitive_meshes.h"
#include "sim/scene/scene_file.h"
#include "test_paths.h"

namespace hd::sim {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(hd::test::source_dir()) / "scenes";

// A minimal valid scene; the broken cases below edit one line of it (line numbers matter).
const std::string kMinimal =
    "name: t\n"                                                    // 1
    "workspace:\n"                                                 // 2
    "  min: [-1, -1, 0.5]\n"                                       // 3
    "  max: [1, 1, 3]\n"                                           // 4
    "cameras:\n"                                                   // 5
    "  - name: c0\n"                                               // 6
    "    d_m: 1.5\n"                                               // 7
    "    intrinsics: {fx: 100, fy: 100, width: 64, height: 48}\n"  // 8
    "    pose: {position: [0, 0, 0]}\n"                            // 9
    "head:\n"                                                      // 10
    "  keyframes:\n"                                               // 11
    "    - {t: 0, position: [0, 0, 0]}\n";                         // 12

std::string replace_line(const std::string& text, int line, const std::string& with) {
  std::string out;
  std::size_t pos = 0;
  for (int i = 1; pos < text.size(); ++i) {
    const std::size_t end = text.find('\n', pos);
    out += (i == line) ? with : text.substr(pos, end - pos + 1);
    pos = end + 1;
  }
  return out;
}

TEST(SceneFile, MinimalSceneParsesWithDefaults) {
  const Scene s = parse_scene(kMinimal, "min.yaml");
  EXPECT_EQ(s.name, "t");
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].name, "c0");
  EXPECT_DOUBLE_EQ(s.cameras[0].p_c.cx, 32.0);  // default: the image centre
  EXPECT_DOUBLE_EQ(s.cameras[0].p_c.cy, 24.0);
  EXPECT_DOUBLE_EQ(s.cameras[0].rate_hz, 30.0);
  EXPECT_TRUE(s.effects.empty());
  EXPECT_EQ(s.head.keyframes.size(), 1u);
}

TEST(SceneFile, DefaultSceneRoundTrip) {
  const Scene s = load_scene((kScenes / "default.yaml").string());
  EXPECT_EQ(s.name, "default");
  EXPECT_DOUBLE_EQ(s.duration_s, 20.0);
  EXPECT_EQ(s.workspace.min_m, Eigen::Vector3d(-1.0, -0.6, 0.8));
  EXPECT_EQ(s.workspace.max_m, Eigen::Vector3d(1.0, 0.4, 2.2));
  ASSERT_EQ(s.geometry.size(), 2u);
  EXPECT_EQ(s.geometry[0].shape, ScenePrimitive::Shape::kQuad);
  EXPECT_EQ(s.geometry[0].size_m, Eigen::Vector3d(1.6, 1.0, 0.0));
  // Table and wall wear photographs (scenes/textures/SOURCE.md), named relative to the scene file.
  EXPECT_EQ(s.geometry[0].texture.kind, SceneTexture::Kind::kImage);
  EXPECT_EQ(s.geometry[0].texture.image_path,
            (kScenes / "textures" / "aloe-cloth-table.png").lexically_normal().string());
  EXPECT_EQ(s.geometry[1].texture.image_path,
            (kScenes / "textures" / "aloe-wall.png").lexically_normal().string());
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[1].carrier, "gripper");
  EXPECT_DOUBLE_EQ(s.objects[1].pick_s, 4.0);
  EXPECT_DOUBLE_EQ(s.objects[1].place_s, 10.0);
  EXPECT_EQ(s.objects[0].keyframes.size(), 9u);
  EXPECT_DOUBLE_EQ(s.objects[0].keyframes[4].yaw_deg, 30.0);
  ASSERT_EQ(s.cameras.size(), 3u);
  EXPECT_DOUBLE_EQ(s.cameras[0].p_c.fx, 420.0);
  // cam0r: cam0's stereo twin, 0.12 m along cam0's own x axis, same orientation.
  EXPECT_EQ(s.cameras[2].name, "cam0r");
  EXPECT_NEAR((s.cameras[2].T_world_cam.t - s.cameras[0].T_world_cam.t -
               s.cameras[0].T_world_cam.R * Eigen::Vector3d(0.12, 0, 0))
                  .norm(),
              0.0, 1e-12);
  EXPECT_NEAR((s.cameras[2].T_world_cam.R - s.cameras[0].T_world_cam.R).norm(), 0.0, 1e-12);
  ASSERT_EQ(s.stereo.size(), 1u);
  EXPECT_EQ(s.stereo[0].left, "cam0");
  EXPECT_EQ(s.stereo[0].right, "cam0r");
  EXPECT_EQ(s.model.moved_objects, MovedObjects::kReconstructed);
  EXPECT_DOUBLE_EQ(s.cameras[0].p_c.distortion[0], -0.12);
  EXPECT_DOUBLE_EQ(s.cameras[0].p_c.distortion[1], 0.03);
  EXPECT_EQ(s.cameras[0].p_c.distortion_count, 5);
  EXPECT_EQ(s.cameras[1].p_c.distortion_count, 0);
  // cam1 looks at the table centre: its optical axis points there, its x axis is horizontal.
  const core::Pose& p1 = s.cameras[1].T_world_cam;
  const Eigen::Vector3d to_target = (Eigen::Vector3d(0, 0.4, 1.4) - p1.t).normalized();
  EXPECT_NEAR(p1.R.col(2).dot(to_target), 1.0, 1e-12);
  EXPECT_NEAR(p1.R.col(0).y(), 0.0, 1e-12);
  EXPECT_TRUE(p1.valid());
  // cam0's pitch of -26.57 deg looks down the ray (0, 0.7, 1.4) to the table centre.
  EXPECT_NEAR(s.cameras[0].T_world_cam.R.col(2).dot(Eigen::Vector3d(0, 0.7, 1.4).normalized()), 1.0,
              1e-7);
  EXPECT_EQ(s.head.keyframes.size(), 5u);
  EXPECT_EQ(s.effects.names(),
            (std::vector<std::string>{"sensor_noise", "camera_delay", "model_staleness"}));
  EXPECT_DOUBLE_EQ(s.effects.camera_delay->mean_ms, 30.0);
  EXPECT_DOUBLE_EQ(s.effects.camera_delay->jitter_ms, 5.0);
  EXPECT_DOUBLE_EQ(s.effects.model_staleness->period_s, 2.0);
  EXPECT_DOUBLE_EQ(*s.station.m_t, 40.0);
}

TEST(SceneFile, EveryShippedSceneLoads) {
  for (const char* name : {"default.yaml", "bare.yaml", "plane.yaml", "all-effects.yaml"}) {
    SCOPED_TRACE(name);
    EXPECT_NO_THROW(load_scene((kScenes / name).string()));
  }
  EXPECT_TRUE(load_scene((kScenes / "bare.yaml").string()).effects.empty());
  EXPECT_EQ(load_scene((kScenes / "all-effects.yaml").string()).effects.names().size(), 11u);
}

struct Broken {
  const char* what;
  std::string text;
  int line;
  const char* field;
  const char* why_contains;
};

TEST(SceneFile, ShippedPhotoTexturesFitTheirSurfaces) {
  // Each scene's image textures decode, with the aspect ratio of the quad they cover: texels are
  // square on it, so the photograph is not stretched.
  for (const char* name : {"default.yaml", "all-effects.yaml"}) {
    SCOPED_TRACE(name);
    const std::string file = (kScenes / name).string();
    const Scene s = load_scene(file);
    int images = 0;
    for (const ScenePrimitive& p : s.geometry) {
      if (p.texture.kind != SceneTexture::Kind::kImage) continue;
      SCOPED_TRACE(p.name);
      ++images;
      const std::vector<render::TexturedMesh> meshes = primitive_meshes(p, file);
      ASSERT_EQ(meshes.size(), 1u);  // a quad
      const render::ImageRgba8& t = meshes[0].texture;
      ASSERT_GT(t.width, 0);
      ASSERT_GT(t.height, 0);
      const double texel_x_m = p.size_m.x() / t.width, texel_y_m = p.size_m.y() / t.height;
      EXPECT_NEAR(texel_x_m / texel_y_m, 1.0, 0.01);
    }
    EXPECT_EQ(images, 2);  // table and back wall
  }
}

TEST(SceneFile, ImageTextureIsReadRelativeToTheSceneFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("scene_file_image_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "tex");
  std::filesystem::copy_file(kScenes / "textures" / "aloe-wall.png", dir / "tex" / "w.png",
                             std::filesystem::copy_options::overwrite_existing);
  const std::string wall =
      "geometry:\n  - {name: w, shape: quad, center: [0, 0, 2], size: [2.4, 1.3],\n"
      "     texture: {type: image, file: tex/w.png}}\n";
  const Scene s = parse_scene(kMinimal + wall, (dir / "s.yaml").string());
  ASSERT_EQ(s.geometry.size(), 1u);
  EXPECT_EQ(s.geometry[0].texture.image_path, (dir / "tex" / "w.png").string());
  // Relative to the scene's folder, not the current directory: elsewhere it is not found.
  try {
    parse_scene(kMinimal + wall, "/nonexistent-dir/s.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.line(), 15) << e.what();
    EXPECT_EQ(e.field(), "geometry[0].texture.file") << e.what();
    EXPECT_NE(e.why().find("not found"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneFile, BrokenFilesNameLineAndField) {
  const std::vector<Broken> cases = {
      {"missing key", replace_line(kMinimal, 7, ""), 6, "cameras[0].d_m", "missing required key"},
      {"wrong type", replace_line(kMinimal, 7, "    d_m: far\n"), 7, "cameras[0].d_m",
       "expected a number"},
      {"out of range",
       replace_line(kMinimal, 8, "    intrinsics: {fx: -100, fy: 100, width: 64, height: 48}\n"), 8,
       "cameras[0].intrinsics.fx", "must be > 0"},
      {"unknown key", replace_line(kMinimal, 9, "    pose: {position: [0, 0, 0]}\n    rate: 30\n"),
       10, "cameras[0].rate", "did you mean 'rate_hz'"},
      {"unknown effect",
       kMinimal + "effects:\n  - camera_delay: {mean_ms: 5}\n  - sensor_nose: {sigma_dn: 2}\n", 15,
       "effects[1]", "did you mean 'sensor_noise'"},
      {"bare unknown effect", kMinimal + "effects:\n  - blurr\n", 14, "effects[0]",
       "unknown effect 'blurr'"},
      {"effect parameter out of range",
       kMinimal + "effects:\n  - dropped_frames: {probability: 1.5}\n", 14,
       "effects[0].dropped_frames.probability", "in [0, 1)"},
      {"bare effect lacks a required parameter", kMinimal + "effects:\n  - motion_blur\n", 14,
       "effects[0].exposure_ms", "missing required key"},
      {"effect listed twice", kMinimal + "effects:\n  - lens_distortion\n  - lens_distortion\n", 15,
       "effects[1]", "listed twice"},
      {"max_video_age_ms out of range",
       replace_line(kMinimal, 7, "    d_m: 2\n    max_video_age_ms: -3\n"), 8,
       "cameras[0].max_video_age_ms", "must be in (0, 60000]"},
      {"bad YAML syntax", replace_line(kMinimal, 9, "    pose: {position: [0, 0, 0]\n"), 10, "",
       "syntax"},
      {"missing calibration file",
       replace_line(replace_line(kMinimal, 9, ""), 8, "    calibration: no-such-calib.yaml\n"), 8,
       "cameras[0].calibration", "not found"},
      {"keyframes out of order", kMinimal + "    - {t: 0, position: [1, 0, 0]}\n", 13,
       "head.keyframes[1].t", "increase"},
      {"unknown carrier",
       kMinimal +
           "objects:\n  - name: b\n    shape: box\n    size: [1, 1, 1]\n    keyframes: [{t: 0, "
           "position: [0, 0, 1]}]\n    carried_by: {object: grip, pick_s: 1, place_s: 2}\n",
       18, "objects[0].carried_by.object", "no other object named 'grip'"},
      {"workspace min above max", replace_line(kMinimal, 4, "  max: [1, -2, 3]\n"), 4,
       "workspace.max", ">= min"},
      {"loop not a bool", kMinimal + "loop: sometimes\n", 13, "loop", "expected true or false"},
      {"stereo pair names an unknown camera", kMinimal + "stereo:\n  - {left: c0, right: c9}\n", 14,
       "stereo[0].right", "no camera named 'c9'"},
      {"stereo pair of one camera", kMinimal + "stereo:\n  - {left: c0, right: c0}\n", 14,
       "stereo[0].right", "two different cameras"},
      {"moved objects misspelt", kMinimal + "model: {moved_objects: groundtruth}\n", 13,
       "model.moved_objects", "ground-truth"},
  };
  for (const Broken& c : cases) {
    SCOPED_TRACE(c.what);
    try {
      parse_scene(c.text, "/tmp/broken.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const config::ConfigError& e) {
      EXPECT_EQ(e.file(), "/tmp/broken.yaml");
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(e.why().find(c.why_contains), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("/tmp/broken.yaml:" + std::to_string(c.line) + ":", 0),
                0u)
          << e.what();
    }
  }
}

TEST(SceneFile, StereoPairsAndMovedObjects) {
  const std::string two = replace_line(kMinimal, 10,
                                       "  - name: c1\n    d_m: 1.5\n    intrinsics: {fx: 100, fy: "
                                       "100, width: 64, height: 48}\n    pose: {position: [0.1, "
                                       "0, 0]}\nhead:\n");
  const Scene plain = parse_scene(two, "s.yaml");
  EXPECT_TRUE(plain.stereo.empty());
  EXPECT_EQ(plain.model.moved_objects, MovedObjects::kReconstructed);  // the default
  const Scene s = parse_scene(two +
                                  "stereo:\n  - {left: c1, right: c0, min_disparity_px: 4, "
                                  "num_disparities_px: 32, matcher: bm, every_updates: 2}\n"
                                  "model: {moved_objects: ground-truth}\n",
                              "s.yaml");
  ASSERT_EQ(s.stereo.size(), 1u);
  EXPECT_EQ(s.stereo[0].left, "c1");
  EXPECT_EQ(s.stereo[0].right, "c0");
  EXPECT_EQ(s.stereo[0].min_disparity_px, 4);
  EXPECT_EQ(s.stereo[0].num_disparities_px, 32);
  EXPECT_EQ(s.stereo[0].matcher, "bm");
  EXPECT_EQ(s.stereo[0].every_updates, 2);
  EXPECT_EQ(s.model.moved_objects, MovedObjects::kGroundTruth);
  try {
    parse_scene(two + "stereo:\n  - {left: c1, right: c0, matcher: sgm}\n", "s.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.field(), "stereo[0].matcher") << e.what();
    EXPECT_NE(e.why().find("sgbm-scaled"), std::string::npos) << e.what();
  }
}

TEST(SceneFile, CameraFromCalibrationFile) {
  const auto dir = std::filesystem::temp_directory_path() / "hd_scene_file_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cam.yaml")
      << "%YAML:1.0\n---\n"
         "image_width: 64\nimage_height: 48\n"
         "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n"
         "   dt: d\n   data: [ 110., 0., 31.5, 0., 112., 23.5, 0., 0., 1. ]\n"
         "distortion_coefficients: !!opencv-matrix\n   rows: 1\n"
         "   cols: 5\n   dt: d\n   data: [ -0.2, 0.05, 0., 0., 0. ]\n";
  std::ofstream(dir / "s.yaml") << replace_line(
      replace_line(kMinimal, 8, "    calibration: cam.yaml\n"), 9,
      "    pose: {position: [0.1, 0, 0]}\n");
  const Scene s = load_scene((dir / "s.yaml").string());
  const core::Pinhole& k = s.cameras[0].p_c;
  EXPECT_DOUBLE_EQ(k.fx, 110.0);
  EXPECT_DOUBLE_EQ(k.fy, 112.0);
  EXPECT_DOUBLE_EQ(k.cx, 32.0);  // OpenCV's 31.5 (centres at integers) is core's image centre
  EXPECT_DOUBLE_EQ(k.cy, 24.0);
  EXPECT_EQ(k.width, 64);
  EXPECT_DOUBLE_EQ(k.distortion[0], -0.2);
  EXPECT_EQ(s.cameras[0].calibration_file, (dir / "cam.yaml").string());
  EXPECT_DOUBLE_EQ(s.cameras[0].T_world_cam.t.x(), 0.1);
  std::filesystem::remove_all(dir);
}

TEST(SceneFile, ObjectPoseFollowsKeyframesAndCarrier) {
  const Scene s = load_scene((kScenes / "default.yaml").string());
  // Gripper: halfway between t = 5 (-0.3, 0.10, 1.3) and t = 8 (0.3, 0.10, 1.5, yaw 30).
  const core::Pose g = object_pose_at(s, 0, 6.5);
  EXPECT_NEAR((g.t - Eigen::Vector3d(0.0, 0.10, 1.4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(g.R).angle(), 15.0 * M_PI / 180.0, 1e-12);
  // Block: at rest until picked at 4 s.
  EXPECT_NEAR((object_pose_at(s, 1, 3.9).t - Eigen::Vector3d(-0.3, 0.36, 1.3)).norm(), 0, 1e-12);
  // Carried: gripped at 4 s with the gripper at (-0.3, 0.27, 1.3), 0.09 m above the block's
  // centre; at 7 s the gripper is 2/3 of the way from (-0.3, 0.10, 1.3) to (0.3, 0.10, 1.5).
  EXPECT_NEAR(
      (object_pose_at(s, 1, 7.0).t - Eigen::Vector3d(0.1, 0.19, 1.3 + 0.2 * 2.0 / 3.0)).norm(), 0,
      1e-12);
  // Put down at 10 s on the table at (0.3, 0.36, 1.5) (the 30 deg yaw turns about the vertical
  // through the gripper, leaving the block below it) and left there.
  EXPECT_NEAR((object_pose_at(s, 1, 10.0).t - Eigen::Vector3d(0.3, 0.36, 1.5)).norm(), 0, 1e-12);
  EXPECT_NEAR((object_pose_at(s, 1, 17.0).t - Eigen::Vector3d(0.3, 0.36, 1.5)).norm(), 0, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(object_pose_at(s, 1, 17.0).R).angle(), 30.0 * M_PI / 180.0, 1e-12);
}

TEST(SceneFile, LoopedSceneRepeatsObjectMotionEveryDuration) {
  Scene s = load_scene((kScenes / "default.yaml").string());
  EXPECT_FALSE(s.loop);
  EXPECT_TRUE(parse_scene(kMinimal + "loop: true\n", "l.yaml").loop);
  // Not looped: after the 20 s scene the block stays where it was put down.
  EXPECT_NEAR((object_pose_at(s, 1, 27.0).t - Eigen::Vector3d(0.3, 0.36, 1.5)).norm(), 0, 1e-12);
  s.loop = true;
  // Looped: 27 s is 7 s into the second lap, the block in the gripper again (see above).
  EXPECT_NEAR(
      (object_pose_at(s, 1, 27.0).t - Eigen::Vector3d(0.1, 0.19, 1.3 + 0.2 * 2.0 / 3.0)).norm(), 0,
      1e-12);
  EXPECT_NEAR((object_pose_at(s, 0, 46.5).t - Eigen::Vector3d(0.0, 0.10, 1.4)).norm(), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(motion_time_s(s, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(motion_time_s(s, 20.0), 0.0);
  EXPECT_DOUBLE_EQ(motion_time_s(s, 3600.0 + 3.5), 3.5);
  EXPECT_DOUBLE_EQ(motion_time_s(s, -1.0), -1.0);
}

}  // namespace
}  // namespace hd::sim
