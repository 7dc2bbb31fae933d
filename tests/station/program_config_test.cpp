// station.yaml: a good file reads back its values; each broken snippet is rejected with the
// file, the line (found independently: the snippet marks it with "# <-") and the field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/config/config_error.h"
#include "station/app/station_config.h"

namespace hd::station {
namespace {

namespace fs = std::filesystem;

class StationConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("station_config_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // A calibration as hybrid-calib writes it: fx 510, fy 505, cx 318, cy 242, 640x480, k1 -0.1,
    // centre (0.25, -0.1, 0.05), rotated 90 deg about z.
    write("cam.yaml",
          "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
          "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
          "   data: [ 510., 0., 318., 0., 505., 242., 0., 0., 1. ]\n"
          "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
          "   data: [ -0.1, 0., 0., 0., 0. ]\n"
          "camera_pose_R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
          "   data: [ 0., -1., 0., 1., 0., 0., 0., 0., 1. ]\n"
          "camera_pose_t: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n"
          "   data: [ 0.25, -0.1, 0.05 ]\n");
    write("nopose.yaml",
          "%YAML:1.0\n---\nimage_width: 320\nimage_height: 240\n"
          "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
          "   data: [ 300., 0., 160., 0., 300., 120., 0., 0., 1. ]\n"
          "distortion_coefficients: !!opencv-matrix\n   rows: 4\n   cols: 1\n   dt: d\n"
          "   data: [ 0., 0., 0., 0. ]\n");
    write("garbled.yaml", "%YAML:1.0\n---\nimage_width: 640\n");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

constexpr const char* kGood = R"(cameras:
  - name: left
    id: mock
    calibration: cam.yaml
    d_m: 1.25
    max_video_age_ms: 80
  - id: mock:320x240
    calibration: nopose.yaml
    d_m: 2
    video_view: model-depth
    optional: true
    pose: {position_m: [1, 0, 0], ypr_deg: [90, 0, 0]}
tracker: {id: "1532:0b00"}
display:
  stereo: true
  ipd_m: 0.06
  eye: {width: 400, height: 300, fx: 350}
  rate_hz: 72
  monitor: 1
  fullscreen: true
transition: {mode: abrupt, m_t: 25, eps: 4, hysteresis: 3, time_constant_s: 0}
marking: {style: checker, checker_cell_px: 12}
workspace: {min_m: [-1, -0.5, 0.5], max_m: [1, 0.5, 2]}
tracker_to_workspace: {position_m: [0, -0.2, 0], ypr_deg: [0, 0, 0]}
home_pose: {position_m: [0.1, 0, 0]}
model: {refresh_period_s: 0.5, stereo: [{left: left, right: camera1, num_disparities_px: 32}]}
predictor: cv
)";

TEST_F(StationConfigTest, GoodFileReadsEveryValue) {
  const StationConfig c = parse_station_config(kGood, path("station.yaml"));
  ASSERT_EQ(c.cameras.size(), 2u);
  const CameraConfig& a = c.cameras[0];
  EXPECT_EQ(a.name, "left");
  EXPECT_EQ(a.id, "mock");
  EXPECT_EQ(a.calibration_file, path("cam.yaml"));
  EXPECT_DOUBLE_EQ(a.d_m, 1.25);
  EXPECT_EQ(a.video_view, hd::core::VideoView::kPlane);  // the default
  EXPECT_EQ(c.cameras[1].video_view, hd::core::VideoView::kModelDepth);
  EXPECT_FALSE(a.optional);
  EXPECT_DOUBLE_EQ(a.max_video_age_ms, 80.0);
  // The values written into cam.yaml above.
  EXPECT_DOUBLE_EQ(a.p_c.fx, 510.0);
  EXPECT_DOUBLE_EQ(a.p_c.fy, 505.0);
  // The file's principal point is OpenCV's (318, 242); core's pixel centres are half a pixel on.
  EXPECT_DOUBLE_EQ(a.p_c.cx, 318.5);
  EXPECT_DOUBLE_EQ(a.p_c.cy, 242.5);
  EXPECT_EQ(a.p_c.width, 640);
  EXPECT_EQ(a.p_c.distortion_count, 5);
  EXPECT_DOUBLE_EQ(a.p_c.distortion[0], -0.1);
  EXPECT_TRUE(a.T_world_cam.t.isApprox(Eigen::Vector3d(0.25, -0.1, 0.05)));
  // R maps camera x to world y (the first column of the matrix written row by row).
  EXPECT_TRUE((a.T_world_cam.R * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));

  const CameraConfig& b = c.cameras[1];
  EXPECT_EQ(b.name, "camera1");
  EXPECT_TRUE(b.optional);
  EXPECT_DOUBLE_EQ(b.max_video_age_ms, 0.0);  // the default: derived from the camera's rate
  EXPECT_EQ(b.p_c.width, 320);
  // pose: overrides; yaw 90 deg about world y (R = Ry(90)) turns camera z (forward) to world +x.
  EXPECT_TRUE(b.T_world_cam.t.isApprox(Eigen::Vector3d(1, 0, 0)));
  EXPECT_NEAR((b.T_world_cam.R * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 0.0,
              1e-12);

  EXPECT_EQ(c.tracker.id, "1532:0b00");
  EXPECT_TRUE(c.display.stereo);
  EXPECT_DOUBLE_EQ(c.display.ipd_m, 0.06);
  EXPECT_EQ(c.display.eye.width, 400);
  EXPECT_EQ(c.display.eye.height, 300);
  EXPECT_DOUBLE_EQ(c.display.eye.fx, 350.0);
  EXPECT_DOUBLE_EQ(c.display.eye.fy, 350.0);  // fy defaults to fx
  EXPECT_DOUBLE_EQ(c.display.eye.cx, 200.0);
  EXPECT_DOUBLE_EQ(c.display.rate_hz, 72.0);
  EXPECT_EQ(c.display.monitor, 1);
  EXPECT_EQ(c.transition.mode, core::TransitionMode::kAbrupt);
  EXPECT_DOUBLE_EQ(c.transition.m_t, 25.0);
  EXPECT_DOUBLE_EQ(c.transition.eps, 4.0);
  EXPECT_DOUBLE_EQ(c.transition.hysteresis, 3.0);
  EXPECT_DOUBLE_EQ(c.transition.time_constant_s, 0.0);
  EXPECT_EQ(c.marking.style, core::MarkingStyle::kChecker);
  EXPECT_EQ(c.marking.checker_cell_px, 12);
  EXPECT_TRUE(c.workspace.min_m.isApprox(Eigen::Vector3d(-1, -0.5, 0.5)));
  EXPECT_TRUE(c.T_world_tracker.t.isApprox(Eigen::Vector3d(0, -0.2, 0)));
  EXPECT_TRUE(c.T_world_home.t.isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_DOUBLE_EQ(c.model.refresh_period_s, 0.5);
  EXPECT_TRUE(c.model.scene_file.empty());
  ASSERT_EQ(c.model.stereo.size(), 1u);  // cameras by name; the second one's is "camera1"
  EXPECT_EQ(c.model.stereo[0].left, "left");
  EXPECT_EQ(c.model.stereo[0].right, "camera1");
  EXPECT_EQ(c.model.stereo[0].num_disparities_px, 32);
  EXPECT_EQ(c.model.stereo[0].matcher, "sgbm-scaled");
  EXPECT_EQ(c.predictor, "cv");
}

TEST_F(StationConfigTest, DefaultsWhenOptionalSectionsAreAbsent) {
  const StationConfig c = parse_station_config(
      "cameras: [{id: mock, calibration: cam.yaml, d_m: 1}]\ntracker: {id: mock}\n"
      "workspace: {min_m: [0, 0, 0], max_m: [1, 1, 1]}\n",
      path("station.yaml"));
  const core::TransitionParams t;
  EXPECT_EQ(c.transition.mode, t.mode);
  EXPECT_DOUBLE_EQ(c.transition.m_t, t.m_t);
  EXPECT_DOUBLE_EQ(c.transition.eps, t.eps);
  EXPECT_EQ(c.display.eye.width, 480);
  EXPECT_DOUBLE_EQ(c.display.eye.fx, 0.9 * 480);
  EXPECT_DOUBLE_EQ(c.display.rate_hz, 90.0);
  EXPECT_EQ(c.predictor, "kalman");
  EXPECT_TRUE(c.T_world_tracker.R.isIdentity());
}

TEST_F(StationConfigTest, ANetworkCameraCanDeclareSynchronizedClocksWithTheirError) {
  const std::string tail = "tracker: {id: mock}\nworkspace: {min_m: [0, 0, 0], max_m: [1, 1, 1]}\n";
  const StationConfig c = parse_station_config(
      "cameras:\n"
      "  - {id: rtp://127.0.0.1:5600, calibration: cam.yaml, d_m: 1, clock: synchronized,"
      " clock_error_ms: 2.5}\n"
      "  - {id: rtp://127.0.0.1:5602, calibration: cam.yaml, d_m: 1}\n" +
          tail,
      path("station.yaml"));
  ASSERT_EQ(c.cameras.size(), 2u);
  EXPECT_TRUE(c.cameras[0].clock_synchronized);
  EXPECT_DOUBLE_EQ(c.cameras[0].clock_error_ms, 2.5);
  EXPECT_FALSE(c.cameras[1].clock_synchronized);  // measured by default
}

struct Broken {
  const char* what;
  const char* field;  ///< expected ConfigError::field()
  std::string text;   ///< the offending line ends with "# <-"
};

// Each snippet is a whole file with exactly one mistake.
std::vector<Broken> broken_snippets() {
  const std::string tail = "tracker: {id: mock}\nworkspace: {min_m: [0, 0, 0], max_m: [1, 1, 1]}\n";
  const std::string cam = "cameras:\n  - id: mock\n    calibration: cam.yaml\n    d_m: 1\n";
  return {
      {"missing calibration file", "cameras[0].calibration",
       "cameras:\n  - id: mock\n    calibration: nowhere.yaml   # <-\n    d_m: 1\n" + tail},
      {"calibration file without its keys", "cameras[0].calibration",
       "cameras:\n  - id: mock\n    calibration: garbled.yaml   # <-\n    d_m: 1\n" + tail},
      {"calibration without a pose and no pose given", "cameras[0].calibration",
       "cameras:\n  - id: mock\n    calibration: nopose.yaml   # <-\n    d_m: 1\n" + tail},
      {"bad transition mode", "transition.mode",
       cam + tail + "transition:\n  mode: sideways   # <-\n"},
      {"bad marking style", "marking.style", cam + tail + "marking: {style: glow}   # <-\n"},
      {"m_t out of range", "transition.m_t", cam + tail + "transition:\n  m_t: -5   # <-\n"},
      {"eps not a number", "transition.eps", cam + tail + "transition:\n  eps: wide   # <-\n"},
      {"d_m zero", "cameras[0].d_m",
       "cameras:\n  - id: mock\n    calibration: cam.yaml\n    d_m: 0   # <-\n" + tail},
      {"bad video view", "cameras[0].video_view", cam + "    video_view: hologram   # <-\n" + tail},
      {"unknown key at the top", "transitions", cam + tail + "transitions: {m_t: 3}   # <-\n"},
      {"unknown key in a camera", "cameras[0].dm",
       "cameras:\n  - id: mock\n    calibration: cam.yaml\n    d_m: 1\n    dm: 2   # <-\n" + tail},
      {"rate out of range", "display.rate_hz", cam + tail + "display:\n  rate_hz: 0   # <-\n"},
      {"workspace min above max", "workspace.max_m",
       cam + "tracker: {id: mock}\nworkspace:\n  min_m: [0, 0, 0]\n  max_m: [1, -1, 1]   # <-\n"},
      {"bad predictor", "predictor", cam + tail + "predictor: magic   # <-\n"},
      {"stereo pair names an unknown camera", "model.stereo[0].right",
       cam + tail + "model:\n  stereo:\n    - {left: camera0, right: nope}   # <-\n"},
      {"max_video_age_ms zero", "cameras[0].max_video_age_ms",
       cam + "    max_video_age_ms: 0   # <-\n" + tail},
      {"model ages the wrong way round", "marking.model_age_full_ms",
       cam + tail + "marking:\n  model_age_fresh_ms: 500\n  model_age_full_ms: 400   # <-\n"},
      {"stale fade out of range", "marking.stale_fade",
       cam + tail + "marking: {stale_fade: 2}   # <-\n"},
      {"max_video_age_ms not a number", "cameras[0].max_video_age_ms",
       cam + "    max_video_age_ms: soon   # <-\n" + tail},
      {"unknown clock", "cameras[0].clock",
       "cameras:\n  - id: rtp://127.0.0.1:5600\n    calibration: cam.yaml\n    d_m: 1\n"
       "    clock: guessed   # <-\n" +
           tail},
      {"a local camera has no sender clock", "cameras[0].clock",
       cam + "    clock: synchronized   # <-\n" + tail},
      {"negative clock error", "cameras[0].clock_error_ms",
       "cameras:\n  - id: rtp://127.0.0.1:5600\n    calibration: cam.yaml\n    d_m: 1\n"
       "    clock: synchronized\n    clock_error_ms: -1   # <-\n" +
           tail},
  };
}

int marked_line(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find("# <-") != std::string::npos) return n;
  return -1;
}

TEST_F(StationConfigTest, BrokenSnippetsNameFileLineAndField) {
  for (const Broken& b : broken_snippets()) {
    SCOPED_TRACE(b.what);
    const int line = marked_line(b.text);
    ASSERT_GT(line, 0);
    const std::string file = path("station.yaml");
    try {
      parse_station_config(b.text, file);
      ADD_FAILURE() << "accepted";
    } catch (const config::ConfigError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_EQ(e.field(), b.field) << e.what();
      const std::string prefix = file + ":" + std::to_string(line) + ":";
      EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
    }
  }
}

TEST_F(StationConfigTest, MissingSectionsAndSyntaxErrorsAreConfigErrors) {
  // No tracker: the error names the missing key.
  try {
    parse_station_config(
        "cameras: [{id: mock, calibration: cam.yaml, d_m: 1}]\n"
        "workspace: {min_m: [0, 0, 0], max_m: [1, 1, 1]}\n",
        path("station.yaml"));
    ADD_FAILURE() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.field(), "tracker") << e.what();
  }
  // A YAML syntax error carries its line.
  try {
    parse_station_config("cameras: [\ntracker: {id: mock\n", path("station.yaml"));
    ADD_FAILURE() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_GT(e.line(), 0) << e.what();
  }
  // An unreadable file is named.
  try {
    load_station_config(path("absent.yaml"));
    ADD_FAILURE() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("absent.yaml"), std::string::npos);
  }
}

TEST(StationConfigNames, EnumSpellingsFollowTheCoreEnums) {
  EXPECT_STREQ(transition_mode_name(core::TransitionMode::kAbrupt), "abrupt");
  EXPECT_STREQ(transition_mode_name(core::TransitionMode::kGlobalBlend), "global_blend");
  EXPECT_STREQ(transition_mode_name(core::TransitionMode::kPerPixel), "per_pixel");
  EXPECT_STREQ(marking_style_name(core::MarkingStyle::kNone), "none");
  EXPECT_STREQ(marking_style_name(core::MarkingStyle::kFrame), "frame");
  EXPECT_STREQ(marking_style_name(core::MarkingStyle::kDesaturate), "desaturate");
  EXPECT_STREQ(marking_style_name(core::MarkingStyle::kChecker), "checker");
}

}  // namespace
}  // namespace hd::station
