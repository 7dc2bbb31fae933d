// hybrid-station run against Aravis's fake GigE camera that is killed in the middle of the run
// and restarted 4 s (of station frames) later -- issue 11's "Done when": no frame is marked
// video or hybrid while its video is older than 250 ms, and the camera's video is back on screen
// within 1 s of its first new frame. Every step waits for what the station itself reports (its
// event lines, its progress lines' frame counts); the assertions read frames.csv, latency.csv and
// summary.json. The frame times inside and outside the outage are printed side by side (a timing
// figure: scripts/outage-frame-times.py prints the same from any run's outputs), not asserted.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/gige/fake_gige_camera.h"
#include "render/latency/latency_recorder.h"
#include "support/text_file.h"
#include "test_paths.h"
#include "test_spawn.h"

namespace {

namespace fs = std::filesystem;
using hd::station::testing::slurp;

constexpr const char* kSerial = "STATIONOUT";
constexpr const char* kId = "Aravis-Fake-STATIONOUT";
constexpr double kRateHz = 90.0;
constexpr int64_t kMs = 1'000'000;

// hybrid-station as a child whose stdout the test reads line by line as it is printed.
class Station {
 public:
  explicit Station(const std::vector<std::string>& args) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    std::vector<std::string> words{hd::test::station_bin()};
    words.insert(words.end(), args.begin(), args.end());
    pid_ = hd::test::spawn(words, {fds[1], {}, true});
    if (pid_ < 0) throw std::runtime_error(std::string("could not start ") + words[0]);
    ::close(fds[1]);
    out_ = ::fdopen(fds[0], "r");
  }
  ~Station() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (out_) std::fclose(out_);
  }

  // Reads lines until `match` accepts one; false at the end of the output (the station exited:
  // its own --seconds bounds every wait).
  bool wait_for(const std::function<bool(const std::string&)>& match) {
    char* line = nullptr;
    std::size_t cap = 0;
    bool found = false;
    while (!found && ::getline(&line, &cap, out_) > 0) {
      log_ += line;
      found = match(line);
    }
    std::free(line);
    return found;
  }
  // Interrupts the run (it writes its outputs) and returns its exit code.
  int finish() {
    ::kill(pid_, SIGINT);
    wait_for([](const std::string&) { return false; });
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  const std::string& log() const { return log_; }

 private:
  pid_t pid_ = -1;
  std::FILE* out_ = nullptr;
  std::string log_;
};

// The number right after `key` in `line`, when `line` holds `key` after `after` (or anywhere when
// `after` is empty); -1 otherwise. (No std::regex: GCC 12's <regex> trips -Wmaybe-uninitialized
// under the sanitizers.)
long number_after(const std::string& line, const std::string& after, const std::string& key) {
  std::size_t from = 0;
  if (!after.empty()) {
    from = line.find(after);
    if (from == std::string::npos) return -1;
  }
  const std::size_t at = line.find(key, from);
  if (at == std::string::npos) return -1;
  const std::size_t digits = at + key.size();
  if (digits >= line.size() || line[digits] < '0' || line[digits] > '9') return -1;
  return std::stol(line.substr(digits));
}

// "  [     3 s] frames 270, ..." -> 270; -1 for another line.
long progress_frames(const std::string& line) {
  const std::size_t open = line.find_first_not_of(' ');
  if (open == std::string::npos || line[open] != '[') return -1;
  return number_after(line, " s] ", "frames ");
}

// "camera front: usable from frame 893 (video 21 ms old)" -> 893 when `usable` matches.
long event_frame(const std::string& line, bool usable) {
  return number_after(
      line, "", usable ? "camera front: usable from frame " : "camera front: unusable from frame ");
}

struct FrameCsvRow {
  uint64_t frame = 0;
  int camera = -1;
  std::string variant;
  double video_age_ms = NAN;
};

std::vector<FrameCsvRow> read_frames_csv(const fs::path& p) {
  std::ifstream f(p);
  std::string line;
  std::getline(f, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    for (std::string c; std::getline(h, c, ',');) header.push_back(c);
  }
  const auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_frame = col("frame"), c_cam = col("camera"), c_var = col("variant"),
                    c_age = col("video_age_ms");
  std::vector<FrameCsvRow> rows;
  while (std::getline(f, line)) {
    std::vector<std::string> v;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) v.push_back(c);
    if (line.back() == ',') v.push_back("");
    FrameCsvRow r;
    r.frame = std::stoull(v.at(c_frame));
    r.camera = std::stoi(v.at(c_cam));
    r.variant = v.at(c_var);
    r.video_age_ms = v.at(c_age).empty() ? NAN : std::stod(v.at(c_age));
    rows.push_back(r);
  }
  return rows;
}

double p99_ms(std::vector<int64_t> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(v.size())));
  return 1e-6 * static_cast<double>(v[std::clamp<std::size_t>(k, 1, v.size()) - 1]);
}

TEST(StationGigeOutage, AKilledCameraIsNeverShownStaleAndIsBackWithinASecondOfItsReturn) {
  const fs::path dir =
      fs::temp_directory_path() / ("station_gige_outage_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The mock station's 640x480 calibration (the fake camera is set to it), alone, and no
  // tracker (an optional one that is not there): the head stays at the camera, m stays ~0, so
  // any frame that is not video is the age rule's doing.
  const fs::path station = dir / "station.yaml";
  std::ofstream(station) << "cameras:\n  - name: front\n    id: " << kId
                         << "\n    calibration: " << hd::test::source_dir()
                         << "/scenes/station-mock/cam0.yaml\n    d_m: 1.5\n"
                            "tracker: {id: /dev/hidraw-not-there, optional: true}\n"
                            "display: {stereo: false, eye: {width: 160, height: 120, fx: 130}, "
                            "rate_hz: 90}\n"
                            "transition: {mode: per_pixel, time_constant_s: 0.15}\n"
                            "workspace: {min_m: [-1, -0.6, 0.8], max_m: [1.4, 0.6, 2.6]}\n";
  const fs::path out = dir / "out";

  std::optional<hd::drivers::testing::FakeGigeCamera> camera;
  camera.emplace(kSerial);
  // 120 s is only the run's bound: the test interrupts it once its steps are done.
  Station run({"run", "--config", station.string(), "--headless", "--seconds", "120", "--progress",
               "0.1", "--out", out.string()});

  // 1. The camera's video is on screen, for a second of station frames.
  long usable_at = -1;
  ASSERT_TRUE(run.wait_for([&](const std::string& l) {
    return (usable_at = event_frame(l, true)) >= 0;
  })) << run.log();
  // A late frame on a loaded machine may make it unusable for a moment: the second starts over
  // then, so the camera is usable when it is killed and step 2 sees the kill's own event.
  ASSERT_TRUE(run.wait_for([&](const std::string& l) {
    if (event_frame(l, false) >= 0) usable_at = -1;
    if (const long f = event_frame(l, true); f >= 0) usable_at = f;
    return usable_at >= 0 && progress_frames(l) >= usable_at + static_cast<long>(kRateHz);
  })) << run.log();

  // 2. Killed: wait until the station says it no longer shows it as live, then 4 s of its frames
  // (a short stretch of late frames on a loaded machine, usable again at once, starts over).
  camera.reset();
  long unusable_at = -1;
  ASSERT_TRUE(run.wait_for([&](const std::string& l) {
    if (const long f = event_frame(l, false); f >= 0) unusable_at = f;
    if (event_frame(l, true) >= 0) unusable_at = -1;
    return unusable_at >= 0 && progress_frames(l) >= unusable_at + static_cast<long>(4 * kRateHz);
  })) << run.log();

  // 3. Back: wait for the station to show it again, then a second more of frames.
  camera.emplace(kSerial);
  long back_at = -1;
  ASSERT_TRUE(run.wait_for([&](const std::string& l) {
    return (back_at = event_frame(l, true)) >= 0;
  })) << run.log();
  ASSERT_TRUE(run.wait_for([&](const std::string& l) {
    return progress_frames(l) >= back_at + static_cast<long>(kRateHz);
  })) << run.log();
  ASSERT_EQ(run.finish(), 0) << run.log();

  const std::vector<FrameCsvRow> rows = read_frames_csv(out / "frames.csv");
  const std::vector<hd::render::LatencyRecord> lat =
      hd::render::LatencyRecorder::read_csv((out / "latency.csv").string());
  ASSERT_EQ(rows.size(), lat.size());
  const nlohmann::json summary = nlohmann::json::parse(slurp(out / "summary.json"));

  // No frame marked video or hybrid shows video older than 250 ms (latency.csv's own stamps),
  // and frames.csv's video age is that same age.
  int live = 0, stale_live = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].frame, lat[i].frame);
    if (rows[i].variant == "synthetic") continue;
    ++live;
    ASSERT_NE(lat[i].video_ns, 0) << "frame " << rows[i].frame << " marked " << rows[i].variant;
    const int64_t age_ns = lat[i].predicted_display_ns - lat[i].video_ns;
    stale_live += age_ns > 250 * kMs;
    EXPECT_NEAR(rows[i].video_age_ms, 1e-6 * static_cast<double>(age_ns), 1e-3);
  }
  EXPECT_EQ(stale_live, 0);
  EXPECT_GT(live, static_cast<int>(kRateHz));

  // The outage as the station recorded it: at least 4 s of frames, the camera then unusable.
  // Other, short intervals are late frames on a loaded machine; the outage is the one from the
  // frame the station reported.
  const nlohmann::json& intervals = summary["cameras"][0]["unusable_intervals"];
  std::size_t outage = intervals.size();
  for (std::size_t i = 0; i < intervals.size(); ++i)
    if (intervals[i]["from_frame"].get<long>() == unusable_at) outage = i;
  ASSERT_LT(outage, intervals.size()) << intervals.dump();
  const nlohmann::json& u = intervals[outage];
  ASSERT_FALSE(u["to_frame"].is_null());
  EXPECT_EQ(u["to_frame"].get<long>(), back_at);
  EXPECT_GE(back_at - unusable_at, static_cast<long>(4 * kRateHz));
  EXPECT_GT(summary["frames_stale_blocked"].get<long>(), static_cast<long>(4 * kRateHz));
  for (const FrameCsvRow& r : rows) {
    if (r.frame >= static_cast<uint64_t>(unusable_at) && r.frame < static_cast<uint64_t>(back_at)) {
      EXPECT_TRUE(r.variant == "synthetic" || r.video_age_ms < 250.0) << r.frame;
    }
  }

  // Back within 1 s of its first new frame, on frame timestamps: the first frame after the
  // outage showing this camera's video is displayed < 1 s after that frame's exposure.
  const int64_t first_new_ns = u["first_new_frame_ns"].get<int64_t>();
  ASSERT_GT(first_new_ns, 0);
  std::optional<std::size_t> shown_again;
  for (std::size_t i = 0; i < rows.size() && !shown_again; ++i)
    if (rows[i].frame >= static_cast<uint64_t>(unusable_at) && rows[i].camera == 0 &&
        rows[i].variant != "synthetic" && lat[i].video_ns >= first_new_ns)
      shown_again = i;
  ASSERT_TRUE(shown_again);
  const double back_s =
      1e-9 * static_cast<double>(lat[*shown_again].predicted_display_ns - first_new_ns);
  EXPECT_LT(back_s, 1.0);
  EXPECT_EQ(rows[*shown_again].frame, static_cast<uint64_t>(back_at));

  // Frame time (draw + swap) inside the 4 s of the outage and outside it: printed, not asserted
  // (a timing figure; under load both grow). The README quotes an idle run's.
  std::vector<int64_t> inside, outside;
  const uint64_t outage_end =
      static_cast<uint64_t>(unusable_at) + static_cast<uint64_t>(4 * kRateHz);
  for (const hd::render::LatencyRecord& r : lat) {
    if (r.frame < 30) continue;  // warm-up
    (r.frame >= static_cast<uint64_t>(unusable_at) && r.frame < outage_end ? inside : outside)
        .push_back(r.swap_ns - r.render_start_ns);
  }
  std::printf(
      "frame time (draw + swap) p99: outage %.3f ms (%zu frames), outside %.3f ms (%zu "
      "frames); video back %.0f ms after the camera's first new frame\n",
      p99_ms(inside), inside.size(), p99_ms(outside), outside.size(), 1e3 * back_s);
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
