// hybrid-station run --config with a network camera (rtp://127.0.0.1:PORT) fed by the issue's
// plain standard sender, gst-launch-1.0 ... x264enc tune=zerolatency ! rtph264pay ! udpsink, on
// a free loopback port: the camera is shown (video frames, the video variant), the start report
// says its p_c comes from the station's calibration file and its capture time is its arrival.
#include <fcntl.h>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <cstdlib>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "drivers/rtp/gst_launch_sender.h"
#include "support/text_file.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using hd::drivers::testing::GstLaunch;
using hd::station::testing::replaced;
using hd::station::testing::slurp;

// hybrid-station as a child whose stdout is read line by line while it runs.
class StationProcess {
 public:
  explicit StationProcess(const std::vector<std::string>& args, const fs::path& err) {
    int fds[2];
    EXPECT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    std::vector<std::string> words{hd::test::station_bin()};
    words.insert(words.end(), args.begin(), args.end());
    pid_ = hd::test::spawn(words, {fds[1], err.string()});
    EXPECT_GT(pid_, 0) << "could not start " << words[0];
    ::close(fds[1]);
    out_ = ::fdopen(fds[0], "r");
  }
  ~StationProcess() { wait(); }

  /// Reads stdout until a line contains `text` (true) or the program ends (false).
  bool read_until(const std::string& text) {
    char line[4096];
    while (std::fgets(line, sizeof line, out_) != nullptr) {
      all_ += line;
      if (std::string(line).find(text) != std::string::npos) return true;
    }
    return false;
  }
  /// Reads stdout until `done(line)` holds for a line (true) or the program ends (false).
  template <class Done>
  bool read_until_line(Done done) {
    char line[4096];
    while (std::fgets(line, sizeof line, out_) != nullptr) {
      all_ += line;
      if (done(std::string(line))) return true;
    }
    return false;
  }
  /// Asks the station to stop as Ctrl-C would: it finishes the frame and writes every output.
  void interrupt() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
  }
  /// Reads the rest of stdout and returns the exit code.
  int wait() {
    if (pid_ <= 0) return code_;
    read_until("\x01never");
    std::fclose(out_);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return code_;
  }
  const std::string& out() const { return all_; }

 private:
  pid_t pid_ = -1;
  FILE* out_ = nullptr;
  std::string all_;
  int code_ = -1;
};

// A station file in a new folder `dir` with one network camera `id`, calibrated at the plain
// sender's size (videotestsrc: 320x240; the mock station's calibration with its size changed),
// with `key_line` ("" or "    key_file: ...\n").
void write_station(const fs::path& dir, const std::string& id, const std::string& key_line) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string cal = slurp(fs::path(hd::test::source_dir()) / "scenes/station-mock/cam0.yaml");
  cal = replaced(cal, "image_width: 640", "image_width: 320");
  cal = replaced(cal, "image_height: 480", "image_height: 240");
  std::ofstream(dir / "cam.yaml") << cal;
  std::ofstream(dir / "station.yaml")
      << "cameras:\n  - name: net\n    id: " << id << "\n    calibration: cam.yaml\n    d_m: 1.5\n"
      << key_line
      << "tracker: {id: mock}\n"
         "display: {stereo: false, eye: {width: 160, height: 120, "
         "fx: 130}}\n"
         "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n";
}

fs::path test_dir(const std::string& name) {
  return fs::temp_directory_path() /
         ("station_rtp_camera_test_" + std::to_string(::getpid()) + "_" + name);
}

void write_key(const fs::path& file, mode_t mode) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(fd, 0);
  const char* hex = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b\n";
  ASSERT_EQ(::write(fd, hex, 57), 57);
  ::fchmod(fd, mode);
  ::close(fd);
}

TEST(StationRtpCamera, ThePlainGstLaunchSenderIsShownAsACamera) {
  const fs::path dir = test_dir("plain");
  const uint16_t port = hd::drivers::testing::free_rtp_port();
  ASSERT_NE(port, 0);
  const std::string id = "rtp://127.0.0.1:" + std::to_string(port);
  write_station(dir, id, "");
  const fs::path out = dir / "out";
  // The run lasts until the station has shown the sender's video (its own event line, then a
  // progress line counting video frames), however long a loaded machine takes to start the
  // sender; the 600 s only bound a hang.
  StationProcess station({"run", "--config", (dir / "station.yaml").string(), "--headless",
                          "--seconds", "600", "--progress", "1", "--out", out.string()},
                         dir / "stderr.txt");
  // The sender starts once the station listens: a plain sender sends its SPS/PPS with its first
  // key frame only, and cannot be asked for another (it has no RTCP).
  ASSERT_TRUE(station.read_until("net (" + id + ")")) << station.out() << slurp(dir / "stderr.txt");
  GstLaunch sender(hd::drivers::testing::plain_sender_pipeline(port));
  ASSERT_TRUE(station.read_until("camera net: usable from frame"))
      << station.out() << slurp(dir / "stderr.txt");
  ASSERT_TRUE(station.read_until_line([](const std::string& l) {
    const std::size_t at = l.find("; video ");
    return l.find("] frames ") != std::string::npos && at != std::string::npos &&
           std::atol(l.c_str() + at + 8) > 0;
  })) << station.out();
  station.interrupt();
  ASSERT_EQ(station.wait(), 0) << station.out() << slurp(dir / "stderr.txt");
  const std::string& report = station.out();
  EXPECT_NE(report.find("camera   ok      net (" + id + ")"), std::string::npos) << report;
  EXPECT_NE(report.find("p_c from the station's calibration file"), std::string::npos) << report;
  EXPECT_NE(report.find("capture time = arrival time"), std::string::npos) << report;
  EXPECT_NE(report.find("RTP receive buffer asked 2097152 B, got "), std::string::npos) << report;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  ASSERT_EQ(s["cameras"].size(), 1u);
  EXPECT_GT(s["cameras"][0]["frames_shown"].get<uint64_t>(), 0u) << s.dump(1);
  EXPECT_EQ(s["cameras"][0]["frames_rejected"].get<uint64_t>(), 0u);
  EXPECT_GT(s["variant_frames"]["video"].get<uint64_t>(), 0u) << s.dump(1);
  ASSERT_EQ(s["network_cameras"].size(), 1u) << s.dump(1);
  const nlohmann::json& n = s["network_cameras"][0];
  EXPECT_EQ(n["security"], "none");
  EXPECT_GT(n["packets"].get<uint64_t>(), 0u);
  EXPECT_EQ(n["malformed_packets"].get<uint64_t>(), 0u);
  EXPECT_EQ(n["frames_with_capture_time"].get<uint64_t>(), 0u);  // a plain sender stamps none
  EXPECT_GT(n["frames_with_arrival_time"].get<uint64_t>(), 0u);
  // No RTCP, so no sender report: the sender clock is never measured, and the summary says so.
  EXPECT_EQ(n["clock"]["mapping"].get<std::string>().rfind("unmeasured", 0), 0u) << n.dump();
  EXPECT_EQ(n["clock"]["sender_reports"].get<uint64_t>(), 0u);
  EXPECT_EQ(n["clock"]["uncertainty_ns"].get<int64_t>(), -1);
  // The receive socket as measured while it ran: its buffer and the kernel's drops on it.
  const nlohmann::json& r = n["receive"];
  EXPECT_EQ(r["buffer_asked_bytes"].get<int64_t>(), 2097152) << r.dump();
  EXPECT_GT(r["buffer_bytes"].get<int64_t>(), 0) << r.dump();
  EXPECT_GT(r["rmem_max_bytes"].get<int64_t>(), 0) << r.dump();
  EXPECT_GE(r["kernel_drops"].get<int64_t>(), 0) << r.dump();
  EXPECT_GT(r["frames_decoded"].get<uint64_t>(), 0u) << r.dump();
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

// Issue 12 item 1: a network camera without a calibration file, fed by hybrid-remote --config (a
// mock camera with its calibration file): not usable until the stream's calibration arrives, then
// shown with it, and the start report, the event line and the summary say where it came from.
TEST(StationRtpCamera, WithoutACalibrationFileTheCameraWaitsForTheStreamsCalibration) {
  const fs::path dir = test_dir("stream_calibration");
  const uint16_t port = hd::drivers::testing::free_rtp_port();
  ASSERT_NE(port, 0);
  const std::string id = "rtp://127.0.0.1:" + std::to_string(port);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "station.yaml")
      << "cameras:\n  - name: net\n    id: " << id << "\n    d_m: 1.5\n"
      << "tracker: {id: mock}\n"
         "display: {stereo: false, eye: {width: 160, height: 120, fx: 130}}\n"
         "workspace: {min_m: [-1, -1, 0.5], max_m: [1, 1, 2]}\n";
  const std::string cal =
      (fs::path(hd::test::source_dir()) / "scenes/station-mock/cam1.yaml").string();
  std::ofstream(dir / "remote.yaml") << "encoder: x264enc\ncameras:\n  - id: mock:320x240\n"
                                     << "    calibration: " << cal << "\n    to: " << id << "\n";
  const fs::path out = dir / "out";
  StationProcess station({"run", "--config", (dir / "station.yaml").string(), "--headless",
                          "--seconds", "600", "--progress", "1", "--out", out.string()},
                         dir / "stderr.txt");
  ASSERT_TRUE(station.read_until("net (" + id + ")")) << station.out() << slurp(dir / "stderr.txt");
  EXPECT_NE(station.out().find("calibration: from the stream (none yet: not shown until"),
            std::string::npos)
      << station.out();
  hd::drivers::testing::ChildProcess remote(
      {hd::test::remote_bin(), "--config", (dir / "remote.yaml").string()});
  ASSERT_TRUE(station.read_until("camera net: calibration: from the stream (revision 1)"))
      << station.out() << slurp(dir / "stderr.txt");
  ASSERT_TRUE(station.read_until("camera net: usable from frame"))
      << station.out() << slurp(dir / "stderr.txt");
  station.interrupt();
  ASSERT_EQ(station.wait(), 0) << station.out() << slurp(dir / "stderr.txt");
  const std::string& report = station.out();
  // The file's values, from the stream (cam1.yaml: fx 250, centre 0.6 m along x).
  const std::size_t cal_at = report.find("calibration: from the stream (revision 1): 320x240");
  ASSERT_NE(cal_at, std::string::npos) << report;
  EXPECT_NE(report.find("centre (0.600, 0.000, 0.000) m", cal_at), std::string::npos) << report;
  // Usable only after the calibration arrived.
  EXPECT_LT(cal_at, report.find("camera net: usable from frame")) << report;
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_GT(s["cameras"][0]["frames_shown"].get<uint64_t>(), 0u) << s.dump(1);
  ASSERT_EQ(s["network_cameras"].size(), 1u) << s.dump(1);
  const nlohmann::json& n = s["network_cameras"][0];
  EXPECT_EQ(n["calibration"], "stream (revision 1)") << n.dump();
  EXPECT_EQ(n["calibration_errors"].get<uint64_t>(), 0u);
  EXPECT_GT(n["frames_with_capture_time"].get<uint64_t>(), 0u);
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

TEST(StationRtpCamera, WithAKeyTheUnencryptedSenderIsNeverShownAndTheReportNamesTheKeyFile) {
  const fs::path dir = test_dir("keyed");
  const uint16_t port = hd::drivers::testing::free_rtp_port();
  ASSERT_NE(port, 0);
  const std::string id = "rtp://127.0.0.1:" + std::to_string(port);
  write_station(dir, id, "    key_file: station.key\n");
  write_key(dir / "station.key", 0600);
  const fs::path out = dir / "out";
  StationProcess station({"run", "--config", (dir / "station.yaml").string(), "--headless",
                          // Long enough for a loaded machine to start the sender, whose
                          // packets must arrive to be rejected.
                          "--seconds", "20", "--out", out.string()},
                         dir / "stderr.txt");
  ASSERT_TRUE(station.read_until("net (" + id + ")")) << station.out() << slurp(dir / "stderr.txt");
  GstLaunch sender(hd::drivers::testing::plain_sender_pipeline(port));
  ASSERT_EQ(station.wait(), 0) << station.out() << slurp(dir / "stderr.txt");
  EXPECT_NE(station.out().find("SRTP AES-128-GCM required (key file " +
                               (dir / "station.key").string() + ")"),
            std::string::npos)
      << station.out();
  EXPECT_EQ(station.out().find("000102030405"), std::string::npos);
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s["cameras"][0]["frames_shown"].get<uint64_t>(), 0u) << s.dump(1);
  EXPECT_EQ(s["variant_frames"]["video"].get<uint64_t>(), 0u) << s.dump(1);
  // Rejected, counted and named in the summary.
  ASSERT_EQ(s["network_cameras"].size(), 1u) << s.dump(1);
  const nlohmann::json& n = s["network_cameras"][0];
  EXPECT_EQ(n["security"], "SRTP AES-128-GCM (key file " + (dir / "station.key").string() + ")");
  EXPECT_GT(n["srtp_rejected_packets"].get<uint64_t>(), 0u) << n.dump();
  EXPECT_NE(station.out().find("rejected"), std::string::npos);
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

TEST(StationRtpCamera, AKeyFileOthersCanReadRefusesTheCamera) {
  const fs::path dir = test_dir("open_key");
  const uint16_t port = hd::drivers::testing::free_rtp_port();
  const std::string id = "rtp://127.0.0.1:" + std::to_string(port);
  write_station(dir, id, "    key_file: station.key\n");
  write_key(dir / "station.key", 0644);
  StationProcess station({"run", "--config", (dir / "station.yaml").string(), "--headless",
                          "--seconds", "2", "--out", (dir / "out").string()},
                         dir / "stderr.txt");
  EXPECT_EQ(station.wait(), 3) << station.out();
  const std::string err = slurp(dir / "stderr.txt") + station.out();
  EXPECT_NE(err.find("mode 0644"), std::string::npos) << err;
  EXPECT_NE(err.find("chmod 600"), std::string::npos) << err;
  EXPECT_EQ(err.find("000102030405"), std::string::npos) << err;
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

}  // namespace
