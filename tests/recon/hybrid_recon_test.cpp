// hybrid-recon end to end: a pair rendered by the station's rasteriser from known cameras, two
// calibration files as hybrid-calib writes them, a PLY out whose vertices lie on the scene's true
// surfaces; bad input gets a message naming the file, exit 2 and no output.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "recon/opencv_camera.h"
#include "rendered_pair.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
namespace rt = hd::recon::testing;
using hd::core::Pose;

struct ToolRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

ToolRun run_tool(const std::string& args) {
  ToolRun r;
  const std::string cmd = std::string(hd::test::recon_bin()) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A calibration file with hybrid-calib's keys: OpenCV's K (pixel centres at integers), five
// distortion coefficients, and the camera's workspace pose.
void write_calibration(const fs::path& path, const hd::core::Pinhole& p, const Pose& pose) {
  cv::FileStorage f(path.string(), cv::FileStorage::WRITE);
  f << "image_width" << p.width << "image_height" << p.height;
  f << "camera_matrix" << cv::Mat(hd::recon::opencv_camera_matrix(p));
  f << "distortion_coefficients" << cv::Mat::zeros(5, 1, CV_64F);
  cv::Mat R(3, 3, CV_64F), t(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) R.at<double>(i, j) = pose.R(i, j);
    t.at<double>(i) = pose.t(i);
  }
  f << "camera_pose_R" << R << "camera_pose_t" << t;
}

struct Ply {
  std::vector<Eigen::Vector3f> vertices;
  std::size_t faces = 0;
  bool ok = false;
};

Ply read_ply(const fs::path& path) {
  Ply ply;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t nv = 0;
  bool binary = false;
  while (std::getline(in, line) && line != "end_header") {
    if (line == "format binary_little_endian 1.0") binary = true;
    if (line.rfind("element vertex ", 0) == 0) nv = std::stoul(line.substr(15));
    if (line.rfind("element face ", 0) == 0) ply.faces = std::stoul(line.substr(13));
  }
  if (!binary || line != "end_header") return ply;
  for (std::size_t i = 0; i < nv; ++i) {
    char b[15];
    if (!in.read(b, sizeof b)) return ply;
    float xyz[3];
    std::memcpy(xyz, b, sizeof xyz);
    ply.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  for (std::size_t i = 0; i < ply.faces; ++i) {
    char b[13];
    if (!in.read(b, sizeof b) || b[0] != 3) return ply;
  }
  ply.ok = true;
  return ply;
}

class HybridRecon : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hybrid_recon_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    T_ = rt::tilted_rig_pose();
    rt::add_standard_scene(scene_, T_);
    rig_ = rt::test_rig(T_);
    cv::Mat l, r, dl, dr;
    scene_.render(rig_.left, rig_.T_world_left, l, dl);
    scene_.render(rig_.right, rig_.T_world_right, r, dr);
    cv::imwrite(path("left.png"), l);
    cv::imwrite(path("right.png"), r);
    write_calibration(path("left.yml"), rig_.left, rig_.T_world_left);
    write_calibration(path("right.yml"), rig_.right, rig_.T_world_right);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string args(const std::string& left = "left.png", const std::string& right = "right.png",
                   const std::string& cl = "left.yml", const std::string& cr = "right.yml") const {
    return "--left " + path(left) + " --right " + path(right) + " --calib-left " + path(cl) +
           " --calib-right " + path(cr) + " --out " + path("mesh.ply") +
           " --min-disparity 8 --num-disparities 96";
  }

  fs::path dir_;
  Pose T_;
  rt::RenderedScene scene_;
  hd::recon::StereoRig rig_;
};

TEST_F(HybridRecon, WritesAMeshWhoseVerticesLieOnTheTrueSurfaces) {
  const ToolRun r = run_tool(args() + " --disparity " + path("d.png"));
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("density"), std::string::npos);
  EXPECT_NE(r.output.find("match"), std::string::npos);
  const Ply ply = read_ply(path("mesh.ply"));
  ASSERT_TRUE(ply.ok);
  ASSERT_GT(ply.vertices.size(), 30000u);
  EXPECT_GT(ply.faces, ply.vertices.size());
  std::vector<double> rel;
  for (const Eigen::Vector3f& v : ply.vertices) {
    const Eigen::Vector3d X = v.cast<double>();
    rel.push_back(scene_.distance(X) / rig_.T_world_left.to_camera(X).z());
  }
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(rel.size() / 2),
                   rel.end());
  const double med = rel[rel.size() / 2];
  std::printf("median distance to the true surface / depth: %.4f %% over %zu vertices\n", 100 * med,
              rel.size());
  EXPECT_LT(med, 0.01);
  // The disparity PNG: 16-bit, the left image's size, d * 16 with 0 = unknown.
  const cv::Mat d = cv::imread(path("d.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(d.type(), CV_16UC1);
  EXPECT_EQ(d.size(), cv::Size(640, 480));
  // An existing output is not overwritten without --force.
  const ToolRun again = run_tool(args());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.output.find("mesh.ply"), std::string::npos);
}

TEST_F(HybridRecon, BadInputNamesTheFileExitsTwoAndWritesNothing) {
  std::ofstream(path("broken.png")) << "not a png";
  cv::Mat small(240, 320, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::imwrite(path("small.png"), small);
  cv::Mat plain(480, 640, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::imwrite(path("plain.png"), plain);
  Pose away = rig_.T_world_right;
  away.R = away.R * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  write_calibration(path("away.yml"), rig_.right, away);
  std::ofstream(path("nopose.yml")) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                       "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n"
                                       "  dt: d\n  data: [500, 0, 319.5, 0, 500, 239.5, 0, 0, 1]\n"
                                       "distortion_coefficients: !!opencv-matrix\n  rows: 5\n"
                                       "  cols: 1\n  dt: d\n  data: [0, 0, 0, 0, 0]\n";
  struct Case {
    std::string what, args, names;
  };
  const std::vector<Case> cases = {
      {"unreadable image", args("broken.png"), "broken.png"},
      {"missing image", args("left.png", "nothing.png"), "nothing.png"},
      {"size not matching the calibration", args("left.png", "small.png"), "small.png"},
      {"cameras not overlapping", args("left.png", "right.png", "left.yml", "away.yml"),
       "away.yml"},
      {"no valid disparity", args("plain.png", "plain.png"), "plain.png"},
      {"calibration without a pose", args("left.png", "right.png", "nopose.yml"), "nopose.yml"},
      {"unknown matcher", args() + " --matcher magic", "magic"},
  };
  for (const Case& c : cases) {
    const ToolRun r = run_tool(c.args);
    std::printf("%s: exit %d: %s", c.what.c_str(), r.exit_code, r.output.c_str());
    EXPECT_EQ(r.exit_code, 2) << c.what << ": " << r.output;
    EXPECT_NE(r.output.find(c.names), std::string::npos) << c.what << ": " << r.output;
    EXPECT_FALSE(fs::exists(path("mesh.ply"))) << c.what;
  }
  const ToolRun help = run_tool("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--calib-left"), std::string::npos);
}

}  // namespace
