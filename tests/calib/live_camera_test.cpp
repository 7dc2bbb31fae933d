// hybrid-calib intrinsics --camera end to end through the camera factory: Aravis's fake GigE
// camera as a real protocol peer, and ids that name no device.
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"
#include "tests/drivers/gige/fake_gige_camera.h"

namespace hd::calib {
namespace {

using test::q;
using test::run_cli;
using test::ScratchDir;

const std::string kBoardArgs = "--board 9x6 --square 0.025";

// The fake camera streams a test pattern, not a chessboard: the honest outcome is frames
// received and counted, "no board", a non-zero exit and no output file. The tool stops at
// --frames 8; --duration is only the cap should frames stop coming, and it sits below ctest's
// 180 s for the GigE tests: 30 s ran out after 7 frames under ASan with the CPUs saturated.
TEST(LiveCalibration, FakeGigeCameraFramesAreCountedAndNoBoardIsReported) {
  drivers::testing::FakeGigeCamera fake("CALIB");
  ScratchDir dir;
  const auto out = dir.path() / "cam.yml";
  const auto r = run_cli("intrinsics --camera Aravis-Fake-CALIB " + kBoardArgs +
                         " --frames 8 --duration 150 --out " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  // One progress line per examined frame, numbered 1..8 (the tool stops at --frames).
  for (int i = 1; i <= 8; ++i)
    EXPECT_NE(r.output.find("[0/15] frame " + std::to_string(i) + ": no board"), std::string::npos)
        << "frame " << i << "\n"
        << r.output;
  EXPECT_EQ(r.output.find("frame 9:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("examined 8 frames from Aravis-Fake-CALIB (0 rejected"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("no 9x6 board found in any of the 8 frames from camera "
                          "Aravis-Fake-CALIB"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(dir.listing().empty()) << r.output;
}

TEST(LiveCalibration, UnknownGigeIdIsAClearError) {
  ScratchDir dir;
  const auto r = run_cli("intrinsics --camera No-Such-Camera-42 " + kBoardArgs + " --out " +
                         q(dir.path() / "cam.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("error: cannot open camera No-Such-Camera-42"), std::string::npos)
      << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

TEST(LiveCalibration, MissingVideoNodeIsAClearError) {
  ScratchDir dir;
  const auto r = run_cli("intrinsics --camera /dev/video99 " + kBoardArgs + " --out " +
                         q(dir.path() / "cam.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("error: cannot open camera /dev/video99"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("No such file or directory"), std::string::npos) << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

TEST(LiveCalibration, MalformedMockIdIsAClearError) {
  ScratchDir dir;
  const auto r =
      run_cli("intrinsics --camera mock:12 " + kBoardArgs + " --out " + q(dir.path() / "cam.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("mock:WxH"), std::string::npos) << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

}  // namespace
}  // namespace hd::calib
