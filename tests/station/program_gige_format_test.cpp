// hybrid-station run against Aravis's fake GigE camera (a real GigE Vision peer on loopback,
// 512x512 at start): a camera is set to its calibrated size and the start report prints what it
// delivers; a size it cannot deliver refuses the start (exit 3) naming the camera and both sizes.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "drivers/gige/fake_gige_camera.h"
#include "support/text_file.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using hd::station::testing::replaced;
using hd::station::testing::slurp;

constexpr const char* kSerial = "STATIONFMT";
constexpr const char* kId = "Aravis-Fake-STATIONFMT";

struct Result {
  int exit_code = -1;
  std::string out, err;
};

class StationGigeFormatTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("station_gige_format_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(dir_, ec);
  }

  // A station file with the fake camera as its one camera, calibrated at width x height (the
  // mock station's calibration with its size changed).
  fs::path station_file(int width, int height) {
    std::string cal = slurp(fs::path(hd::test::source_dir()) / "scenes/station-mock/cam0.yaml");
    cal = replaced(cal, "image_width: 640", "image_width: " + std::to_string(width));
    cal = replaced(cal, "image_height: 480", "image_height: " + std::to_string(height));
    std::ofstream(dir_ / "cam.yaml") << cal;
    const fs::path station = dir_ / "station.yaml";
    std::ofstream(station) << "cameras:\n"
                              "  - name: front\n"
                              "    id: "
                           << kId
                           << "\n"
                              "    calibration: cam.yaml\n"
                              "    d_m: 1.5\n"
                              "tracker: {id: mock}\n"
                              "display: {stereo: false, eye: {width: 160, height: 120, fx: 130}}\n"
                              "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n";
    return station;
  }

  Result run(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = "'" + std::string(hd::test::station_bin()) + "' run " + args + " > '" +
                            out.string() + "' 2> '" + err.string() + "'";
    const int status = std::system(cmd.c_str());
    Result r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }

  fs::path dir_;
};

TEST_F(StationGigeFormatTest, TheCameraIsSetToItsCalibratedSizeAndTheReportSaysWhatItDelivers) {
  hd::drivers::testing::FakeGigeCamera fake(kSerial);  // starts at 512x512
  const fs::path out = dir_ / "out";
  const Result r = run("--config '" + station_file(640, 480).string() +
                       "' --headless --seconds 4 --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   ok      front (" + std::string(kId) + "): 640x480 Mono8 at "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(region at (0, 0), binning 1x1)"), std::string::npos) << r.out;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  ASSERT_EQ(s["cameras"].size(), 1u);
  // The fake camera streams at 25 Hz; a single frame in 4 s is enough to show it was taken.
  EXPECT_GT(s["cameras"][0]["frames_shown"].get<uint64_t>(), 0u);
  EXPECT_EQ(s["cameras"][0]["frames_rejected"].get<uint64_t>(), 0u);
  EXPECT_TRUE(s["camera_events"].empty()) << s["camera_events"].dump();
}

TEST_F(StationGigeFormatTest, ASizeTheCameraCannotDeliverRefusesTheStartNamingBothSizes) {
  hd::drivers::testing::FakeGigeCamera fake(kSerial);  // a 2048x2048 sensor, at 512x512
  const Result r = run("--config '" + station_file(4000, 3000).string() +
                       "' --headless --seconds 4 --out '" + (dir_ / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   MISSING front (" + std::string(kId) + ")"), std::string::npos)
      << r.out;
  for (const std::string& part :
       {std::string("front (") + kId + ")", std::string("calibrated at 4000x3000"),
        std::string("the camera delivers 512x512, not the requested 4000x3000"),
        std::string("Width 4000 is outside the camera's 1..2048"),
        std::string("Recalibrate it at 512x512"),
        std::string("set its region (Width, Height, and binning) so that it delivers 4000x3000")})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << "\n" << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "summary.json"));
}

}  // namespace
