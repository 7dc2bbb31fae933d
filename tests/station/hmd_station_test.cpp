// display.hmd in station.yaml: the neutral profile changes nothing, an HMD profile sets the eyes
// its lens needs and the panel picture, a bad inline profile names the station file's line.
#include <gtest/gtest.h>

#include <string>

#include "core/config/config_error.h"
#include "render/lens/lens_warp.h"
#include "station/app/station_config.h"
#include "station/app/station_parts.h"
#include "test_paths.h"

namespace hd::station {
namespace {

const std::string kDir = std::string(hd::test::source_dir()) + "/scenes/";

// scenes/station-mock.yaml's cameras and workspace, with the given display section.
std::string station_text(const std::string& display) {
  return "cameras:\n  - {id: mock, calibration: station-mock/cam0.yaml, d_m: 1.5}\n"
         "tracker: {id: mock}\n" +
         display + "workspace: {min_m: [-1, -0.6, 0.8], max_m: [1.4, 0.6, 2.6]}\n";
}

StationFrameConfig configured(const StationConfig& c, const RunOptions& o = {}) {
  StationParts p;
  configure_frame(p, c.display, c.transition, c.marking, c.workspace, c.predictor, o);
  return p.frame_config;
}

void expect_same_pinhole(const core::Pinhole& a, const core::Pinhole& b) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.fx, b.fx);
  EXPECT_EQ(a.fy, b.fy);
  EXPECT_EQ(a.cx, b.cx);
  EXPECT_EQ(a.cy, b.cy);
}

TEST(HmdStation, NeutralProfileIsTheStationWithoutOne) {
  const std::string display = "display: {eye: {width: 320, height: 240, fx: 260}, ";
  const StationConfig none = parse_station_config(station_text(display + "}\n"), kDir + "a.yaml");
  const StationConfig neutral =
      parse_station_config(station_text(display + "hmd: neutral}\n"), kDir + "b.yaml");
  EXPECT_TRUE(neutral.display.hmd.neutral);
  const StationFrameConfig a = configured(none), b = configured(neutral);
  EXPECT_EQ(a.lens, nullptr);
  EXPECT_EQ(b.lens, nullptr);
  for (std::size_t e = 0; e < 2; ++e) expect_same_pinhole(a.rig.eye[e], b.rig.eye[e]);
  EXPECT_EQ(a.picture_width(), b.picture_width());
  EXPECT_EQ(a.picture_width(), 640);  // two 320 px eyes side by side, as before
  EXPECT_EQ(a.picture_height(), 240);
}

TEST(HmdStation, ProfileSetsTheEyesTheLensNeedsAndThePanel) {
  const StationConfig c = parse_station_config(
      station_text("display: {eye: {width: 320, height: 240}, hmd: osvr-hdk-1.3}\n"),
      kDir + "c.yaml");
  const StationFrameConfig f = configured(c);
  ASSERT_NE(f.lens, nullptr);
  const render::lens::LensWarp w(c.display.hmd);
  for (int e = 0; e < 2; ++e) expect_same_pinhole(f.rig.eye[static_cast<std::size_t>(e)], w.eye(e));
  EXPECT_TRUE(f.rig.stereo);
  EXPECT_EQ(f.picture_width(), 1920);
  EXPECT_EQ(f.picture_height(), 1080);
  // p_o is the lens's: wider than the pinhole the display section asked for.
  EXPECT_GT(w.eye_fov_x_deg(), 90.0);
  // --mono drops the profile.
  RunOptions mono;
  mono.mono = true;
  EXPECT_EQ(configured(c, mono).lens, nullptr);
}

TEST(HmdStation, BadInlineProfileNamesTheStationFileLineAndField) {
  const std::string text = station_text(
      "display:\n"
      "  hmd:\n"
      "    name: mine\n"
      "    panel: {width_px: 1920, height_px: 1080, width_m: 0.12, height_m: 0.07}\n"
      "    lens_centre_m: {left: [0.03, 0.035], right: [0.03, 0.035]}\n"
      "    distortion: {model: polynomial, coefficients: [0, 1], r_unit_m: 0.06}\n"
      "    fov_deg: [185, 90]\n");
  try {
    parse_station_config(text, kDir + "bad.yaml");
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.line(), 10) << e.what();
    EXPECT_EQ(e.field(), "display.hmd.fov_deg[0]") << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.yaml:10:"), std::string::npos) << e.what();
    EXPECT_NE(e.why().find("185"), std::string::npos) << e.what();
  }
  try {
    parse_station_config(station_text("display: {hmd: oculus-dk9}\n"), kDir + "bad.yaml");
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.field(), "display.hmd") << e.what();
    EXPECT_NE(std::string(e.what()).find("osvr-hdk-1.3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hd::station
