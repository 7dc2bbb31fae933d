// A detection abandoned at its deadline (calib/corner_detector.h) must not abort the program's
// exit: the worker, still inside OpenCV when OpenCV's statics were destroyed, made hybrid-calib
// exit with SIGABRT ("Can't fetch data from terminated TLS container") instead of its own code.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corner_detector.h"

namespace hd::calib {
namespace {

// A large noise picture: no board, and the SB detector's search takes seconds on it, so the
// worker is certainly still running when the 1 ms deadline has passed and the process exits.
TEST(AbandonedDetectionDeathTest, TheProgramExitsWithItsOwnCodeWhileAWorkerIsStillRunning) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        cv::Mat noise(600, 800, CV_8UC1);
        cv::randu(noise, 0, 256);
        DetectorOptions opt;
        opt.timeout = std::chrono::milliseconds(1);
        const Detection d = detect_corners(noise, Board::parse("9x6", 0.025), opt);
        std::exit(d.status == DetectionStatus::kTimedOut ? 3 : 4);
      },
      ::testing::ExitedWithCode(3), "");
}

}  // namespace
}  // namespace hd::calib
