#pragma once
// Helpers shared by the calib tests: the data folder, a scratch folder, running the CLI.

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include "test_paths.h"

namespace hd::calib::test {

namespace fs = std::filesystem;

/// The shared data set folder; FAILS (not skips) the calling test when it is missing.
inline fs::path data_dir(const std::string& sub) {
  const fs::path p = fs::path(hd::test::calib_data_dir()) / sub;
  EXPECT_TRUE(fs::is_directory(p))
      << "calibration data missing: " << p << " (shared/ must sit beside the checkout)";
  return p;
}

/// A fresh folder removed at the end of the test.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("hd_calib_test_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  std::vector<std::string> listing() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(path_)) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }

 private:
  fs::path path_;
};

struct RunResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs hybrid-calib with `args` (already shell-quoted where needed).
inline RunResult run_cli(const std::string& args) {
  const std::string cmd = std::string("'") + hd::test::calib_bin() + "' " + args + " 2>&1";
  RunResult r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The camera matrix exactly as the file holds it (OpenCV's numbers), read without calib's reader.
inline cv::Matx33d file_camera_matrix(const fs::path& p) {
  cv::FileStorage fs(p.string(), cv::FileStorage::READ);
  cv::Mat K;
  fs["camera_matrix"] >> K;
  EXPECT_EQ(K.total(), 9u) << p;
  if (K.total() != 9) return cv::Matx33d::eye();
  K.convertTo(K, CV_64F);
  return cv::Matx33d(K);
}

inline std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

}  // namespace hd::calib::test
