// The two-process demo (issue 12 item 6): hybrid-remote --scene renders the default scene's three
// cameras and sends them as RTP H.264 on loopback, hybrid-station run --scene --cameras-from
// receives them; both share one scene clock (--scene-epoch). A lighter copy of the default scene
// (cameras at 15 Hz, no sensor noise, a model refresh every second) keeps the test short. The
// test waits for the station's own lines (each network camera's first frame, then a progress line
// with video shown and a stereo reconstruction made), stops it like Ctrl-C and checks from its
// outputs: video from the network shown as video, every frame stamped with the sender's capture
// time (on the remote's exposure grid of the shared epoch), the reconstruction made from received
// pairs, and no frame marked video or hybrid whose video was older than the age rule allows.
#include <gtest/gtest.h>

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/rtp/gst_launch_sender.h"
#include "render/latency/latency_recorder.h"
#include "support/program_process.h"
#include "support/text_file.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using hd::station::testing::ProgramProcess;
using hd::station::testing::replaced;
using hd::station::testing::slurp;

constexpr double kCameraRateHz = 15.0;

int64_t clock_ns(clockid_t id) {
  timespec t{};
  ::clock_gettime(id, &t);
  return int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

// "... live while under 398 ms old" of the start report's first network camera, in ms.
double live_bound_ms(const std::string& report) {
  const std::string key = "live while under ";
  const std::size_t at = report.find(key, report.find("net:cam0"));
  return at == std::string::npos ? NAN : std::atof(report.c_str() + at + key.size());
}

// The column `name` of frames.csv, by frame.
std::vector<std::string> csv_column(const fs::path& file, const std::string& name) {
  std::ifstream f(file);
  std::string line;
  std::getline(f, line);
  std::vector<std::string> header;
  std::stringstream h(line);
  for (std::string c; std::getline(h, c, ',');) header.push_back(c);
  std::size_t col = header.size();
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) col = i;
  EXPECT_LT(col, header.size()) << name;
  std::vector<std::string> out;
  while (std::getline(f, line)) {
    std::vector<std::string> v;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) v.push_back(c);
    if (!line.empty() && line.back() == ',') v.push_back("");
    out.push_back(col < v.size() ? v[col] : "");
  }
  return out;
}

TEST(StationTwoProcesses, TheRemotesCamerasAreShownReconstructedAndNeverShownOld) {
  const fs::path dir =
      fs::temp_directory_path() / ("station_two_process_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string scene = slurp(fs::path(hd::test::source_dir()) / "scenes/default.yaml");
  for (int i = 0; i < 3; ++i) scene = replaced(scene, "    rate_hz: 30\n", "    rate_hz: 15\n");
  scene = replaced(scene, "  - sensor_noise: {sigma_dn: 2, seed: 1}\n", "");
  scene = replaced(scene, "model_staleness: {period_s: 2, delay_s: 0.3}",
                   "model_staleness: {period_s: 1, delay_s: 0.1}");
  std::ofstream(dir / "scene.yaml") << scene;
  // Its image textures are named relative to the scene file: beside the copy, they are found.
  fs::copy(fs::path(hd::test::source_dir()) / "scenes" / "textures", dir / "textures");
  const uint16_t port = hd::drivers::testing::free_rtp_port(3);
  ASSERT_NE(port, 0);
  const std::string to = "rtp://127.0.0.1:" + std::to_string(port);
  // Scene t = 0 shortly ahead; both programs wait for it (a late start only joins later).
  const int64_t epoch_realtime_ns = clock_ns(CLOCK_REALTIME) + 1'500'000'000;
  char epoch[64];
  std::snprintf(epoch, sizeof epoch, "%" PRId64 ".%09" PRId64, epoch_realtime_ns / 1'000'000'000,
                epoch_realtime_ns % 1'000'000'000);
  const int64_t epoch_mono_ns =
      epoch_realtime_ns - (clock_ns(CLOCK_REALTIME) - clock_ns(CLOCK_MONOTONIC));

  const fs::path out = dir / "out";
  // --seconds and --camera-wait only bound a hang: the test stops the run by its events.
  ProgramProcess station(hd::test::station_bin(),
                         {"run",
                          "--scene",
                          (dir / "scene.yaml").string(),
                          "--headless",
                          "--mono",
                          "--eye-width",
                          "160",
                          "--eye-height",
                          "120",
                          "--rate",
                          "30",
                          "--progress",
                          "1",
                          "--seconds",
                          "600",
                          "--camera-wait",
                          "300",
                          "--cameras-from",
                          to,
                          "--scene-epoch",
                          epoch,
                          "--out",
                          out.string()},
                         dir / "station_stderr.txt");
  // The remote starts once the station has assembled its cameras (its start report's end).
  ASSERT_TRUE(station.read_until("  outputs "))
      << station.out() << slurp(dir / "station_stderr.txt");
  ProgramProcess remote(hd::test::remote_bin(),
                        {"--scene", (dir / "scene.yaml").string(), "--to", to, "--scene-epoch",
                         epoch, "--seconds", "180"},
                        dir / "remote_stderr.txt");
  // Each network camera's first frame, in whatever order they come.
  std::vector<std::string> waiting{"camera net:cam0: first frame", "camera net:cam1: first frame",
                                   "camera net:cam0r: first frame"};
  ASSERT_TRUE(station.read_until_line([&](const std::string& l) {
    for (std::size_t i = 0; i < waiting.size(); ++i)
      if (l.find(waiting[i]) != std::string::npos) waiting.erase(waiting.begin() + i--);
    return waiting.empty();
  })) << station.out()
      << slurp(dir / "station_stderr.txt");
  // A progress line with video shown and a reconstruction from the received pair.
  ASSERT_TRUE(station.read_until_line([](const std::string& l) {
    const std::size_t v = l.find("; video "), r = l.find("stereo reconstructions ");
    return l.find("] frames ") != std::string::npos && v != std::string::npos &&
           r != std::string::npos && std::atol(l.c_str() + v + 8) > 0 &&
           std::atol(l.c_str() + r + 23) > 0;
  })) << station.out()
      << slurp(dir / "station_stderr.txt");
  station.interrupt();
  ASSERT_EQ(station.wait(), 0) << station.out() << slurp(dir / "station_stderr.txt");
  remote.interrupt();
  EXPECT_EQ(remote.wait(), 0) << remote.out() << slurp(dir / "remote_stderr.txt");

  const std::string& report = station.out();
  EXPECT_NE(report.find("cameras:         from the network: camera i on 127.0.0.1:" +
                        std::to_string(port) + " + 2 i"),
            std::string::npos)
      << report;
  // The shared epoch takes the clocks to agree: capture times are mapped through them as well.
  EXPECT_NE(report.find("mapped through this host's CLOCK_REALTIME (clock: synchronized"),
            std::string::npos)
      << report;
  EXPECT_NE(remote.out().find("scene time: t = 0 at --scene-epoch " + std::string(epoch)),
            std::string::npos)
      << remote.out();
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s["cameras_from"], to);
  EXPECT_EQ(s["scene_epoch"], epoch);
  EXPECT_GT(s["variant_frames"]["video"].get<uint64_t>(), 0u) << s.dump(1);
  EXPECT_GT(s["cameras"][0]["frames_shown"].get<uint64_t>(), 0u) << s.dump(1);
  EXPECT_GT(s["reconstructions"].get<uint64_t>(), 0u) << s.dump(1);
  ASSERT_EQ(s["network_cameras"].size(), 3u) << s.dump(1);
  for (const nlohmann::json& n : s["network_cameras"]) {
    EXPECT_GT(n["packets"].get<uint64_t>(), 0u) << n.dump();
    EXPECT_EQ(n["malformed_packets"].get<uint64_t>(), 0u) << n.dump();
    // Every decoded frame carried hybrid-remote's capture time, none fell back to its arrival.
    EXPECT_GT(n["frames_with_capture_time"].get<uint64_t>(), 0u) << n.dump();
    EXPECT_EQ(n["frames_with_arrival_time"].get<uint64_t>(), 0u) << n.dump();
  }

  // Frames shown with video: the video's time is the remote's exposure, on its grid
  // epoch + k / 15 Hz of the shared scene clock (the sender's capture time mapped back, not the
  // arrival), and no frame marked video or hybrid showed video older than 1.5 x the camera's
  // bound (docs/truth.md: older video is never drawn).
  const double bound_ms = live_bound_ms(report);
  ASSERT_TRUE(std::isfinite(bound_ms)) << report;
  const std::vector<hd::render::LatencyRecord> lat =
      hd::render::LatencyRecorder::read_csv((out / "latency.csv").string());
  const std::vector<std::string> variants = csv_column(out / "frames.csv", "variant");
  ASSERT_EQ(variants.size(), lat.size());
  const auto period_ns = static_cast<int64_t>(std::llround(1e9 / kCameraRateHz));
  int live = 0, stale_live = 0, off_grid = 0;
  for (std::size_t i = 0; i < lat.size(); ++i) {
    if (variants[i] == "synthetic") continue;
    ++live;
    ASSERT_NE(lat[i].video_ns, 0) << "frame " << lat[i].frame << " marked " << variants[i];
    EXPECT_TRUE(lat[i].video_is_exposure) << lat[i].frame;
    const int64_t since_epoch = lat[i].video_ns - epoch_mono_ns;
    // 0.2 ms: the three processes read the realtime - monotonic offset each at its own instant.
    constexpr int64_t kClockReads_ns = 200'000;
    EXPECT_GE(since_epoch, -kClockReads_ns) << lat[i].frame;
    const int64_t off = (since_epoch % period_ns + period_ns) % period_ns;
    off_grid += std::min(off, period_ns - off) > kClockReads_ns;
    const double age_ms = 1e-6 * static_cast<double>(lat[i].predicted_display_ns - lat[i].video_ns);
    stale_live += age_ms > 1.5 * bound_ms;
  }
  EXPECT_GT(live, 0);
  EXPECT_EQ(off_grid, 0);
  EXPECT_EQ(stale_live, 0) << "bound " << bound_ms << " ms";
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

}  // namespace
