// hybrid-station run, as a user runs it: the built program on the default scene and on the mock
// station config writes every output with one row per frame and values in range; the video reads
// back with the frame count the run reports; broken files and missing devices exit non-zero with
// a message naming the file:line:field or the device.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "render/latency/latency_recorder.h"
#include "support/text_file.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using hd::station::testing::slurp;
using hd::station::testing::split_csv_line;

struct Result {
  int exit_code = -1;
  std::string out, err;
};

class StationRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("station_run_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!HasFailure()) fs::remove_all(dir_, ec);
  }

  // Runs the built hybrid-station in `cwd` with `args`.
  Result run(const std::string& args, const fs::path& cwd = hd::test::source_dir()) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = "cd '" + cwd.string() + "' && '" +
                            std::string(hd::test::station_bin()) + "' run " + args + " > '" +
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

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
};

CsvTable read_csv(const fs::path& p) {
  CsvTable t;
  std::ifstream f(p);
  std::string line;
  if (!std::getline(f, line)) return t;
  t.header = split_csv_line(line);
  while (std::getline(f, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    EXPECT_EQ(cells.size(), t.header.size()) << line;
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size() && i < t.header.size(); ++i)
      row[t.header[i]] = cells[i];
    t.rows.push_back(row);
  }
  return t;
}

// frames.csv: one row per frame, in order, each value in its range, the variant consistent with
// w_video (video: 1, synthetic: 0, hybrid: in between) and the camera name with its index.
void check_frames_csv(const fs::path& p, uint64_t frames,
                      const std::vector<std::string>& camera_names) {
  const CsvTable t = read_csv(p);
  const std::vector<std::string> expected_header = {"frame",
                                                    "t_s",
                                                    "m",
                                                    "w_video",
                                                    "camera",
                                                    "camera_name",
                                                    "variant",
                                                    "missed_deadline",
                                                    "guidance",
                                                    "guidance_distance_m",
                                                    "guidance_dir_x",
                                                    "guidance_dir_y",
                                                    "head_x_m",
                                                    "head_y_m",
                                                    "head_z_m",
                                                    "video_age_ms",
                                                    "model_age_ms"};
  ASSERT_EQ(t.header, expected_header);
  ASSERT_EQ(t.rows.size(), frames);
  double last_t = -1.0;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    auto r = t.rows[i];
    SCOPED_TRACE("row " + std::to_string(i));
    EXPECT_EQ(std::stoull(r["frame"]), i);
    const double ts = std::stod(r["t_s"]);
    EXPECT_GE(ts, last_t);
    last_t = ts;
    const double m = r["m"] == "inf" ? INFINITY : std::stod(r["m"]);
    EXPECT_GE(m, 0.0);
    const double w = std::stod(r["w_video"]);
    EXPECT_GE(w, 0.0);
    EXPECT_LE(w, 1.0);
    const int cam = std::stoi(r["camera"]);
    EXPECT_GE(cam, -1);
    EXPECT_LT(cam, static_cast<int>(camera_names.size()));
    EXPECT_EQ(r["camera_name"], cam >= 0 ? camera_names[static_cast<std::size_t>(cam)] : "");
    if (cam < 0) {
      EXPECT_TRUE(std::isinf(m));
    }
    const std::string v = r["variant"];
    if (v == "video")
      EXPECT_EQ(w, 1.0);
    else if (v == "synthetic")
      EXPECT_EQ(w, 0.0);
    else if (v == "hybrid")
      EXPECT_TRUE(w > 0.0 && w < 1.0) << w;
    else
      ADD_FAILURE() << "variant " << v;
    EXPECT_TRUE(r["missed_deadline"] == "0" || r["missed_deadline"] == "1");
    EXPECT_TRUE(r["guidance"] == "0" || r["guidance"] == "1");
    for (const char* k : {"head_x_m", "head_y_m", "head_z_m"})
      EXPECT_TRUE(std::isfinite(std::stod(r[k])));
    // A video age exactly when video is on screen; a model age whenever the model has one.
    EXPECT_EQ(r["video_age_ms"].empty(), v == "synthetic") << r["video_age_ms"];
    if (!r["video_age_ms"].empty()) {
      EXPECT_GT(std::stod(r["video_age_ms"]), -5.0);
    }
    if (!r["model_age_ms"].empty()) {
      EXPECT_GT(std::stod(r["model_age_ms"]), -5.0);
    }
  }
}

void expect_png(const fs::path& p, int min_width, int min_height) {
  const cv::Mat img = cv::imread(p.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << p;
  EXPECT_GE(img.cols, min_width) << p;
  EXPECT_GE(img.rows, min_height) << p;
}

nlohmann::json summary(const fs::path& dir) {
  return nlohmann::json::parse(slurp(dir / "summary.json"));
}

// Frames in a video, counted by decoding them all (not the container's claim).
int decoded_frames(const fs::path& p, cv::Size& size) {
  cv::VideoCapture cap(p.string());
  if (!cap.isOpened()) return -1;
  int n = 0;
  cv::Mat f;
  while (cap.read(f)) {
    size = f.size();
    ++n;
  }
  return n;
}

TEST_F(StationRunTest, DefaultSceneWritesEveryOutputAndTheVideoReadsBack) {
  const fs::path out = dir_ / "out";
  const Result r =
      run("--scene scenes/default.yaml --headless --frames 60 --eye-width 160 "
          "--eye-height 120 --png-every 20 --video '" +
          (out / "run.avi").string() + "' --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   ok      sim:cam0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tracker  ok      sim:head"), std::string::npos) << r.out;

  check_frames_csv(out / "frames.csv", 60, {"sim:cam0", "sim:cam1", "sim:cam0r"});
  // The run waits for the head: even frame 0 is drawn from camera 0's place, where the default
  // scene's head starts (0, -0.3, 0), not from the tracker origin.
  const CsvTable frames = read_csv(out / "frames.csv");
  ASSERT_FALSE(frames.rows.empty());
  EXPECT_NEAR(std::stod(frames.rows[0].at("head_y_m")), -0.3, 0.01);
  EXPECT_EQ(hd::render::LatencyRecorder::read_csv((out / "latency.csv").string()).size(), 60u);
  expect_png(out / "latency.png", 100, 100);
  expect_png(out / "trace.png", 1200, 720);
  expect_png(out / "contact_sheet.png", 160, 60);

  const nlohmann::json s = summary(out);
  EXPECT_EQ(s["frames"].get<uint64_t>(), 60u);
  EXPECT_EQ(s["frames_csv_rows"].get<uint64_t>(), 60u);
  // Every frame went to the video unless the writer was behind, which the run counts.
  const uint64_t video = s["video_frames"].get<uint64_t>();
  EXPECT_GT(video, 0u);
  EXPECT_EQ(video + s["recorder_dropped"].get<uint64_t>(), 60u);
  cv::Size size;
  EXPECT_EQ(decoded_frames(out / "run.avi", size), static_cast<int>(video));
  EXPECT_EQ(size, cv::Size(2 * 160, 120));  // stereo: both eyes side by side
  // PNG frames at 0, 20, 40 (each one the run says it wrote exists).
  int pngs = 0;
  for (const char* name : {"frame_000000.png", "frame_000020.png", "frame_000040.png"})
    if (fs::exists(out / name)) {
      expect_png(out / name, 320, 120);
      ++pngs;
    }
  EXPECT_EQ(pngs, s["png_frames"].get<int>());
  // Nothing half-written is left behind.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// At 1000 Hz no machine draws a stereo frame in 0.85 ms: held, the station slows to a rate it
// can draw at and reports it; fixed, it keeps 1000 Hz. Either way every frame and every miss is
// tallied against the rate it ran at.
TEST_F(StationRunTest, ARateTheMachineCannotHoldIsLoweredWhenHeldAndKeptWhenFixed) {
  for (const std::string policy : {"hold", "fixed"}) {
    const fs::path out = dir_ / policy;
    // The default eyes (480x400, stereo): several ms a frame on any CPU.
    const Result r =
        run("--scene scenes/default.yaml --headless --frames 120 --rate 1000 "
            "--rate-policy " +
            policy + " --out '" + out.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const nlohmann::json s = summary(out);
    EXPECT_EQ(s["rate_policy"], policy);
    EXPECT_DOUBLE_EQ(s["rate_hz"].get<double>(), 1000.0);
    uint64_t frames = 0, missed = 0;
    double slowest = 1e9;
    for (const nlohmann::json& rate : s["rates"]) {
      frames += rate["frames"].get<uint64_t>();
      missed += rate["missed_deadlines"].get<uint64_t>();
      slowest = std::min(slowest, rate["rate_hz"].get<double>());
    }
    EXPECT_EQ(frames, 120u) << s.dump(1);
    EXPECT_EQ(missed, s["missed_deadlines"].get<uint64_t>()) << s.dump(1);
    if (policy == "hold") {
      EXPECT_NE(r.out.find("rate             1000.0 Hz display; held"), std::string::npos) << r.out;
      EXPECT_GE(s["rate_changes"].get<uint64_t>(), 1u) << s.dump(1);
      EXPECT_LT(slowest, 1000.0) << s.dump(1);
      EXPECT_NE(r.out.find("rate 1000.0 Hz -> "), std::string::npos) << r.out;
    } else {
      EXPECT_EQ(s["rate_changes"].get<uint64_t>(), 0u);
      ASSERT_EQ(s["rates"].size(), 1u) << s.dump(1);
      EXPECT_DOUBLE_EQ(s["rates"][0]["rate_hz"].get<double>(), 1000.0);
      EXPECT_GT(missed, 0u);  // the same frames, unheld, miss 1 ms
    }
  }
}

TEST_F(StationRunTest, MockStationConfigRunsItsDevicesAndSkipsTheOptionalMissingOne) {
  const fs::path out = dir_ / "out";
  const Result r =
      run("--config scenes/station-mock.yaml --headless --frames 60 --out '" + out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   ok      front (mock): 640x480 RGBA8 at 30 Hz, calibration"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("camera   ok      side (mock:320x240): 320x240 RGBA8 at 30 Hz"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("camera   skipped spare (/dev/video99)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tracker  ok      mock"), std::string::npos) << r.out;
  check_frames_csv(out / "frames.csv", 60, {"front", "side"});
  for (const char* f : {"latency.csv", "latency.png", "trace.png", "contact_sheet.png"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  const nlohmann::json s = summary(out);
  EXPECT_EQ(s["frames"].get<uint64_t>(), 60u);
  ASSERT_EQ(s["cameras"].size(), 2u);
  EXPECT_EQ(s["cameras"][0]["frames_rejected"].get<uint64_t>(), 0u);
  EXPECT_EQ(s["cameras"][1]["frames_rejected"].get<uint64_t>(), 0u);
  EXPECT_GT(s["head"]["accepted"].get<uint64_t>(), 0u);
}

TEST_F(StationRunTest, LoopStartsTheHeadMotionOverAfterEachLap) {
  // A 2 s scene whose head slides 0.4 m along x in its first second and holds: after the first
  // lap a looped run brings it back to x = 0 (the wrap), a run without --loop keeps it at 0.4.
  const fs::path scene = dir_ / "slide.yaml";
  std::ofstream(scene) << "duration_s: 2\n"
                          "workspace: {min: [-1, -1, 0.5], max: [1, 1, 3]}\n"
                          "geometry: [{shape: quad, center: [0, 0, 2], size: [2, 2]}]\n"
                          "cameras:\n"
                          "  - {name: c0, d_m: 2, pose: {position: [0, 0, 0]},\n"
                          "     intrinsics: {fx: 60, fy: 60, width: 64, height: 48}}\n"
                          "head:\n"
                          "  smooth: false\n"
                          "  keyframes: [{t: 0, position: [0, 0, 0]}, {t: 1, position: [0.4, 0, "
                          "0]}]\n";
  // The smallest head x in the frames after t = 1.2 s of the run.
  const auto late_min_x = [&](const std::string& extra, const fs::path& out) {
    const Result r =
        run("--scene '" + scene.string() + "' --headless --seconds 3.2 " + extra +
            " --predictor none --progress 1 --mono --eye-width 64 --eye-height 48 --out '" +
            out.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    // A progress line a second: at 1, 2 and 3 s (the last only if a frame falls in 3..3.2 s).
    std::size_t lines = 0;
    for (std::size_t at = r.out.find("] frames "); at != std::string::npos;
         at = r.out.find("] frames ", at + 1))
      ++lines;
    EXPECT_GE(lines, 2u) << r.out;
    EXPECT_LE(lines, 3u) << r.out;
    if (!extra.empty()) {
      EXPECT_NE(r.out.find("2 s, motion looped)"), std::string::npos) << r.out;
    }
    double lowest = 1e9;
    int rows = 0;
    for (const auto& row : read_csv(out / "frames.csv").rows) {
      if (std::stod(row.at("t_s")) <= 1.2) continue;
      lowest = std::min(lowest, std::stod(row.at("head_x_m")));
      ++rows;
    }
    EXPECT_GT(rows, 100);
    return lowest;
  };
  EXPECT_GT(late_min_x("", dir_ / "once"), 0.399);
  EXPECT_LT(late_min_x("--loop", dir_ / "looped"), 0.05);
}

TEST_F(StationRunTest, BrokenSceneExitsWithFileLineAndField) {
  std::string text = slurp(fs::path(hd::test::source_dir()) / "scenes" / "default.yaml");
  if (!text.empty() && text.back() != '\n') text += '\n';
  const int line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
  text += "bogus_key: 1\n";
  const fs::path scene = dir_ / "broken.yaml";
  std::ofstream(scene) << text;
  // Its image textures are named relative to the scene file: beside the copy, they are found.
  fs::copy(fs::path(hd::test::source_dir()) / "scenes" / "textures", dir_ / "textures");
  const Result r = run("--scene '" + scene.string() + "' --headless --frames 5 --out '" +
                       (dir_ / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(scene.string() + ":" + std::to_string(line) + ":"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("bogus_key"), std::string::npos) << r.err;
}

TEST_F(StationRunTest, BrokenConfigExitsWithFileLineAndField) {
  const fs::path config = dir_ / "station.yaml";
  const std::string cal =
      (fs::path(hd::test::source_dir()) / "scenes/station-mock/cam0.yaml").string();
  std::ofstream(config) << "cameras: [{id: mock, calibration: '" << cal << "', d_m: 1.5}]\n"
                        << "tracker: {id: mock}\n"
                        << "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n"
                        << "transition:\n"
                        << "  mode: per_pixel\n"
                        << "  m_t: -3\n";
  const Result r = run("--config '" + config.string() + "' --headless --frames 5 --out '" +
                       (dir_ / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(config.string() + ":6:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("transition.m_t"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "frames.csv"));
}

TEST_F(StationRunTest, MissingRequiredDeviceIsNamedWithItsReason) {
  const fs::path config = dir_ / "station.yaml";
  const std::string cal =
      (fs::path(hd::test::source_dir()) / "scenes/station-mock/cam0.yaml").string();
  std::ofstream(config) << "cameras:\n"
                        << "  - {name: main, id: /dev/video98, calibration: '" << cal
                        << "', d_m: 1.5}\n"
                        << "tracker: {id: 'ffff:fffe'}\n"
                        << "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n";
  const Result r = run("--config '" + config.string() + "' --headless --frames 5 --out '" +
                       (dir_ / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   MISSING main (/dev/video98): "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tracker  MISSING ffff:fffe: no HID device ffff:fffe"), std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("/dev/video98"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ffff:fffe"), std::string::npos) << r.err;
}

TEST_F(StationRunTest, ACameraThatCannotDeliverItsCalibratedSizeRefusesTheStart) {
  // A mock delivers exactly the size of its id; calibrated at 640x480, mock:320x240 cannot be
  // set to it, and the run must not start (and then reject every frame).
  const fs::path config = dir_ / "station.yaml";
  const std::string cal =
      (fs::path(hd::test::source_dir()) / "scenes/station-mock/cam0.yaml").string();
  std::ofstream(config) << "cameras:\n"
                        << "  - {name: main, id: 'mock:320x240', calibration: '" << cal
                        << "', d_m: 1.5}\n"
                        << "tracker: {id: mock}\n"
                        << "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n";
  const Result r = run("--config '" + config.string() + "' --headless --frames 5 --out '" +
                       (dir_ / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.out.find("camera   MISSING main (mock:320x240): calibrated at 640x480 (" + cal +
                       "), but the camera delivers 320x240, not the requested 640x480"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("Recalibrate it at 320x240"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("give it the id mock:640x480"), std::string::npos) << r.err;
}

TEST_F(StationRunTest, DefaultSceneIsFoundAndSaysWhere) {
  // From the checkout: scenes/default.yaml in the current directory.
  Result r = run("--headless --frames 3 --eye-width 64 --eye-height 48 --out '" +
                 (dir_ / "a").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("default scene scenes/default.yaml (found in the current directory)"),
            std::string::npos)
      << r.out;
  // From elsewhere: the source tree the program was built from.
  r = run(
      "--headless --frames 3 --eye-width 64 --eye-height 48 --out '" + (dir_ / "b").string() + "'",
      dir_);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("(found in the source tree " + std::string(hd::test::source_dir()) + ")"),
            std::string::npos)
      << r.out;
}

}  // namespace
