// hybrid-bench-calib-cpu: CPU time of `hybrid-calib intrinsics` beside OpenCV's calibration sample
// (samples/cpp/calibration.cpp: findChessboardCorners + cornerSubPix 11x11 + calibrateCameraRO
// with the sample's flags), both run as programs on the same images in the same run, interleaved.
//
//   hybrid-bench-calib-cpu --images ../shared/data/calib/opencv-left --pattern 'left*'
//       --board 9x6 --square 0.025 [--runs 5] [--hybrid-calib PATH] [-- extra hybrid-calib args]
//
// Each program is a child process; its CPU is the child's user + system time from wait4 (all its
// threads, start-up included for both). Prints every run, the medians and their ratio.
#include <fcntl.h>
#include <fnmatch.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace {

struct Options {
  std::string images, pattern = "*", board = "9x6", hybrid_calib = HD_CALIB_EXE;
  double square = 0.025;
  int runs = 5;
  std::vector<std::string> extra;
};

std::vector<std::string> list_images(const std::string& dir, const std::string& pattern) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && fnmatch(pattern.c_str(), name.c_str(), 0) == 0)
      out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// What OpenCV's calibration sample does for an image list with default options (-w -h -s, no -a,
// no -zt, no -p): per image imread (gray), findChessboardCorners(ADAPTIVE_THRESH | FAST_CHECK |
// NORMALIZE_IMAGE), cornerSubPix(11x11, (-1,-1), 30 it / 1e-4); then calibrateCameraRO with
// iFixedPoint = -1 and flags CALIB_FIX_K3 | CALIB_USE_LU, per-view reprojection errors, and the
// result written as FileStorage YAML.
double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

int run_as_sample(const Options& o, const std::string& out) {
  const double cpu_start = process_cpu_s();
  int cols = 0, rows = 0;
  if (std::sscanf(o.board.c_str(), "%dx%d", &cols, &rows) != 2) return 2;
  const cv::Size pattern(cols, rows);
  std::vector<std::vector<cv::Point2f>> image_points;
  cv::Size image_size;
  for (const auto& path : list_images(o.images, o.pattern)) {
    const cv::Mat view = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (view.empty()) continue;
    image_size = view.size();
    std::vector<cv::Point2f> buf;
    if (!cv::findChessboardCorners(
            view, pattern, buf,
            cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_FAST_CHECK | cv::CALIB_CB_NORMALIZE_IMAGE))
      continue;
    cv::cornerSubPix(view, buf, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
    image_points.push_back(std::move(buf));
  }
  const double cpu_detect = process_cpu_s();
  if (image_points.size() < 3) return 1;
  std::vector<cv::Point3f> obj;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      obj.emplace_back(static_cast<float>(c * o.square), static_cast<float>(r * o.square), 0.f);
  std::vector<std::vector<cv::Point3f>> object_points(image_points.size(), obj);
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F), D = cv::Mat::zeros(8, 1, CV_64F), new_obj;
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCameraRO(object_points, image_points, image_size, -1, K, D, rvecs,
                                           tvecs, new_obj, cv::CALIB_FIX_K3 | cv::CALIB_USE_LU);
  const double cpu_calib = process_cpu_s();
  double total = 0;
  std::vector<float> per_view;
  for (std::size_t i = 0; i < image_points.size(); ++i) {
    std::vector<cv::Point2f> proj;
    cv::projectPoints(object_points[i], rvecs[i], tvecs[i], K, D, proj);
    const double e = cv::norm(image_points[i], proj, cv::NORM_L2);
    per_view.push_back(static_cast<float>(std::sqrt(e * e / static_cast<double>(proj.size()))));
    total += e * e;
  }
  cv::FileStorage fs(out, cv::FileStorage::WRITE);
  fs << "image_width" << image_size.width << "image_height" << image_size.height;
  fs << "camera_matrix" << K << "distortion_coefficients" << D;
  fs << "avg_reprojection_error"
     << std::sqrt(total / static_cast<double>(obj.size() * image_points.size()));
  fs << "per_view_reprojection_errors" << cv::Mat(per_view);
  std::printf(
      "sample: %zu views, RMS %.4f px; process CPU after detection %.3f s, after "
      "calibration %.3f s (start-up %.3f s)\n",
      image_points.size(), rms, cpu_detect, cpu_calib, cpu_start);
  return 0;
}

// Runs argv as a child with its output (stdout and stderr) to `out_file`; returns its user +
// system CPU seconds, or -1.
double child_cpu_s(const std::vector<std::string>& args, const std::string& out_file,
                   int* exit_code) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int status = 0;
  rusage ru{};
  if (wait4(pid, &status, 0, &ru) != pid) return -1;
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  const auto s = [](const timeval& t) { return t.tv_sec + 1e-6 * t.tv_usec; };
  return s(ru.ru_utime) + s(ru.ru_stime);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool as_sample = false;
  std::string sample_out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "error: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      std::printf(
          "hybrid-bench-calib-cpu: CPU time of `hybrid-calib intrinsics` beside OpenCV's "
          "calibration sample, both run as programs on the same images, interleaved\n"
          "Usage: hybrid-bench-calib-cpu --images DIR [--pattern GLOB] [--board CxR] "
          "[--square M]\n"
          "         [--runs N] [--hybrid-calib PATH] [-- extra hybrid-calib args]\n"
          "  --images DIR        the checkerboard photos (e.g. ../shared/data/calib/opencv-left)\n"
          "  --pattern GLOB      which files of DIR (default *)\n"
          "  --board CxR         inner corners (default 9x6)\n"
          "  --square M          square size in metres (default 0.025)\n"
          "  --runs N            runs of each program (default 5); medians and their ratio\n"
          "  --hybrid-calib PATH the program to measure (default: this build's)\n");
      return 0;
    } else if (a == "--images")
      o.images = next();
    else if (a == "--pattern")
      o.pattern = next();
    else if (a == "--board")
      o.board = next();
    else if (a == "--square")
      o.square = std::stod(next());
    else if (a == "--runs")
      o.runs = std::stoi(next());
    else if (a == "--hybrid-calib")
      o.hybrid_calib = next();
    else if (a == "--as-sample") {
      as_sample = true;
      sample_out = next();
    } else if (a == "--") {
      o.extra.assign(argv + i + 1, argv + argc);
      break;
    } else {
      std::fprintf(stderr, "error: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  std::error_code ec;
  if (o.images.empty() || !fs::is_directory(o.images, ec)) {
    std::fprintf(stderr, "error: --images DIR: '%s' is not a folder\n", o.images.c_str());
    return 2;
  }
  if (as_sample) return run_as_sample(o, sample_out);

  const fs::path tmp = fs::temp_directory_path() / ("hd_calib_cpu_" + std::to_string(getpid()));
  fs::create_directories(tmp);
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::vector<std::string> sample = {self,
                                           "--images",
                                           o.images,
                                           "--pattern",
                                           o.pattern,
                                           "--board",
                                           o.board,
                                           "--square",
                                           std::to_string(o.square),
                                           "--as-sample",
                                           (tmp / "sample.yml").string()};
  std::vector<std::string> ours = {o.hybrid_calib,
                                   "intrinsics",
                                   "--images",
                                   o.images,
                                   "--pattern",
                                   o.pattern,
                                   "--board",
                                   o.board,
                                   "--square",
                                   std::to_string(o.square),
                                   "--force",
                                   "--out",
                                   (tmp / "ours.yml").string()};
  ours.insert(ours.end(), o.extra.begin(), o.extra.end());
  std::vector<double> t_sample, t_ours;
  std::printf("run  sample_cpu_s  hybrid_calib_cpu_s\n");
  for (int r = 0; r < o.runs; ++r) {
    int e1 = -1, e2 = -1;
    const double a = child_cpu_s(sample, (tmp / "sample.txt").string(), &e1);
    const double b = child_cpu_s(ours, (tmp / "ours.txt").string(), &e2);
    if (a < 0 || b < 0 || e1 != 0 || e2 != 0) {
      std::fprintf(stderr, "error: a child failed (sample exit %d, hybrid-calib exit %d)\n", e1,
                   e2);
      fs::remove_all(tmp, ec);
      return 1;
    }
    t_sample.push_back(a);
    t_ours.push_back(b);
    std::printf("%3d  %12.3f  %18.3f\n", r + 1, a, b);
  }
  // Where each program's CPU went in the last run, as each prints it (hybrid-calib: its core
  // and each extra quality figure).
  std::printf("last run, as the programs report it:\n");
  for (const char* f : {"sample.txt", "ours.txt"}) {
    std::ifstream in(tmp / f);
    for (std::string line; std::getline(in, line);)
      if (line.rfind("sample:", 0) == 0 || line.rfind("  cpu", 0) == 0)
        std::printf("  %s\n", line.c_str());
  }
  fs::remove_all(tmp, ec);
  const double ms = median(t_sample), mo = median(t_ours);
  std::printf(
      "median CPU: OpenCV calibration sample %.3f s, hybrid-calib intrinsics %.3f s, "
      "ratio %.2f (<= 1.00: no more CPU than the sample)\n",
      ms, mo, mo / ms);
  return 0;
}
