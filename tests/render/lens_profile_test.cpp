// HMD profiles: the shipped files read back as published, and bad values are refused naming the
// file, the field and the value.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "render/lens/hmd_profile_file.h"
#include "test_paths.h"

namespace hd::render::lens {
namespace {

const std::string kDir = std::string(hd::test::source_dir()) + "/render/lens/profiles/";

// The message of the refusal, or "" when the profile is accepted.
std::string refusal(const std::string& yaml) {
  try {
    read_hmd_profile(YAML::Load(yaml), "mine.yaml");
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "";
}

const char* kOsvr = R"(name: test
panel: {width_px: 1920, height_px: 1080, width_m: 0.12176, height_m: 0.06849}
lens_centre_m:
  left: [0.028674, 0.034245]
  right: [0.032206, 0.034245]
distortion:
  model: polynomial
  coefficients: [0, 1, -1.74, 5.15, -1.27, -2.23]
  r_unit_m: [0.06088, 0.06849]
fov_deg: [90, 96.73]
)";

std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(HmdProfile, ShippedDk1IsOpenHmdsPolynomialAndTheSdksPanel) {
  const HmdProfile p = load_hmd_profile(kDir + "oculus-dk1.yaml");
  EXPECT_FALSE(p.neutral);
  EXPECT_EQ(p.panel_width_px, 1280);
  EXPECT_EQ(p.panel_height_px, 800);
  EXPECT_DOUBLE_EQ(p.panel_width_m, 0.14976);
  // OpenHMD's a, b, c, d = 1.003, -1.005, 0.403, 0.599 is r (a r^3 + b r^2 + c r + d).
  ASSERT_EQ(p.coefficients.size(), 5u);
  EXPECT_DOUBLE_EQ(p.coefficients[0], 0.0);
  EXPECT_DOUBLE_EQ(p.coefficients[1], 0.599);
  EXPECT_DOUBLE_EQ(p.coefficients[2], 0.403);
  EXPECT_DOUBLE_EQ(p.coefficients[3], -1.005);
  EXPECT_DOUBLE_EQ(p.coefficients[4], 1.003);
  EXPECT_DOUBLE_EQ(p.aberration[0], 0.985);
  EXPECT_DOUBLE_EQ(p.aberration[2], 1.015);
  // Lens centres 0.0635 m apart, symmetric about the panel's middle (0.07488 m).
  EXPECT_NEAR(p.lens_centre_m[0].x(), 0.07488 - 0.03175, 1e-12);
  EXPECT_NEAR(p.lens_centre_m[1].x(), 0.03175, 1e-12);
  EXPECT_NEAR(p.lens_centre_m[0].y(), 0.0468, 1e-12);
  EXPECT_FALSE(p.source.empty());
}

TEST(HmdProfile, ShippedOsvrAndNeutralRead) {
  const HmdProfile o = load_hmd_profile(kDir + "osvr-hdk-1.3.yaml");
  ASSERT_TRUE(o.fov_deg);
  EXPECT_DOUBLE_EQ(o.fov_deg->y(), 96.73);
  EXPECT_EQ(o.coefficients.size(), 6u);
  EXPECT_TRUE(load_hmd_profile(kDir + "neutral.yaml").neutral);
  EXPECT_EQ(find_hmd_profile("osvr-hdk-1.3", "").name, "osvr-hdk-1.3");
}

TEST(HmdProfile, UnknownNameListsTheShippedOnes) {
  try {
    find_hmd_profile("oculus-dk9", "");
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("oculus-dk1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("oculus-dk9"), std::string::npos) << e.what();
  }
}

TEST(HmdProfile, TheTestProfileIsAccepted) {
  EXPECT_EQ(refusal(kOsvr), "");
}

TEST(HmdProfile, FieldOfView180IsRefused) {
  const std::string m = refusal(with(kOsvr, "[90, 96.73]", "[180, 96.73]"));
  EXPECT_NE(m.find("mine.yaml:10:"), std::string::npos) << m;
  EXPECT_NE(m.find("fov_deg[0]: 180"), std::string::npos) << m;
  EXPECT_NE(refusal(with(kOsvr, "[90, 96.73]", "[90, 200]")).find("fov_deg[1]: 200"),
            std::string::npos);
}

TEST(HmdProfile, NonMonotonicPolynomialIsRefusedUnlessClamped) {
  // Halving the radius unit makes the corners reach r = 1.46, past P's turn at r = 0.866.
  const std::string bad = with(kOsvr, "[0.06088, 0.06849]", "[0.03044, 0.034245]");
  const std::string m = refusal(bad);
  EXPECT_NE(m.find("mine.yaml:8:"), std::string::npos) << m;
  EXPECT_NE(m.find("distortion.coefficients: P'(0.866"), std::string::npos) << m;
  EXPECT_NE(m.find("max_radius"), std::string::npos) << m;
  // Blacking out the panel beyond the turn makes it usable.
  EXPECT_EQ(refusal(with(bad, "r_unit_m: [", "max_radius: 0.85\n  r_unit_m: [")), "");
}

TEST(HmdProfile, LensCentreOffThePanelIsRefused) {
  const std::string m = refusal(with(kOsvr, "[0.028674, 0.034245]", "[0.07, 0.034245]"));
  EXPECT_NE(m.find("mine.yaml:4:"), std::string::npos) << m;
  EXPECT_NE(m.find("lens_centre_m.left: [0.07, 0.034245]: off the eye's half"), std::string::npos)
      << m;
  EXPECT_NE(refusal(with(kOsvr, "[0.032206, 0.034245]", "[0.032206, -0.001]"))
                .find("lens_centre_m.right: [0.032206, -0.001]"),
            std::string::npos);
}

TEST(HmdProfile, OtherMistakesNameTheField) {
  EXPECT_NE(refusal(with(kOsvr, "[0, 1,", "[0.1, 1,")).find("distortion.coefficients[0]: 0.1"),
            std::string::npos);
  EXPECT_NE(refusal(with(kOsvr, "name: test", "name: test\ncolour: red")).find("colour: unknown"),
            std::string::npos);
  EXPECT_NE(refusal(with(kOsvr, "width_px: 1920", "width_px: wide"))
                .find("panel.width_px: expected an integer, got 'wide'"),
            std::string::npos);
  const std::string mesh = refusal(with(kOsvr, "model: polynomial", "model: mesh"));
  EXPECT_NE(mesh.find("mine.yaml"), std::string::npos) << mesh;
  EXPECT_NE(mesh.find("distortion.model: mesh"), std::string::npos) << mesh;
  EXPECT_NE(mesh.find("reserved for a future version; this version supports 'openhmd' and "
                      "'polynomial'"),
            std::string::npos)
      << mesh;
  EXPECT_NE(refusal(with(kOsvr, "fov_deg: [90, 96.73]", "aberration: [1, 1, 3]"))
                .find("aberration[2]: 3"),
            std::string::npos);
}

TEST(HmdProfile, MistakesAreReportedAsTheSharedConfigReaderReportsThem) {
  // The profile is read through core/config's reader: its messages, with line and field.
  const std::string missing = [] {
    try {
      load_hmd_profile("/no/such/dir/mine.yaml");
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_EQ(missing.rfind("/no/such/dir/mine.yaml: cannot read", 0), 0u) << missing;
  const std::string many =
      refusal(with(kOsvr, "[0, 1, -1.74,", "[0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0,"));
  EXPECT_NE(many.find("mine.yaml:8:"), std::string::npos) << many;
  EXPECT_NE(
      many.find("distortion.coefficients: expected a list of 2 to 12 numbers, got a list of 14"),
      std::string::npos)
      << many;
  const std::string typo = refusal(with(kOsvr, "model: polynomial", "model: polynomal"));
  EXPECT_NE(typo.find("mine.yaml:7:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("distortion.model: unknown model 'polynomal'; expected openhmd or "
                      "polynomial; did you mean 'polynomial'?"),
            std::string::npos)
      << typo;
  EXPECT_NE(refusal(with(kOsvr, "  left: [0.028674, 0.034245]\n", ""))
                .find("mine.yaml:4:3: "
                      "lens_centre_m.left: "
                      "missing required key"),
            std::string::npos);
}

TEST(HmdProfile, ANodeOfALargerFileNamesItsFieldsFromThatFilesRoot) {
  const config::YamlFields station(
      YAML::Load("display:\n  hmd:\n    name: nested\n    neutral: true\n    colour: red\n"),
      "station.yaml");
  const config::YamlFields hmd = station.required_map("display").required_map("hmd");
  try {
    read_hmd_profile(hmd);
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.field(), "display.hmd.colour") << e.what();
    EXPECT_EQ(e.line(), 5) << e.what();
  }
  // check_profile's problems too.
  const config::YamlFields wrong(YAML::Load(with(kOsvr, "[90, 96.73]", "[185, 96.73]")),
                                 "station.yaml", "display.hmd");
  try {
    read_hmd_profile(wrong);
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.field(), "display.hmd.fov_deg[0]") << e.what();
    EXPECT_EQ(e.line(), 10) << e.what();
    EXPECT_NE(e.why().find("185"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hd::render::lens
