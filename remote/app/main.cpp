// hybrid-remote: the program at the robot's site. Streams each camera to the station as RTP
// H.264 (issue 12): `--scene FILE` renders the simulator's cameras, so the whole system runs as
// two processes on one machine (camera i goes to rtp://HOST:(PORT + 2 i)); `--config remote.yaml`
// sends the site's real cameras (remote/app/config_run.h).
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/config/config_error.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/rtp_uri.h"
#include "drivers/rtp/srtp_key.h"
#include "remote/app/config_run.h"
#include "remote/sender/rtp_sender.h"
#include "sim/scene/scene_file.h"
#include "sim/scene_epoch.h"
#include "sim/simulation.h"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) {
  g_stop = true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-remote: streams the remote site's cameras to the operator's station as RTP H.264 "
      "(x264enc zerolatency, rtpbin with RTCP), every packet stamped with the frame's capture "
      "time (RFC 6051 ntp-64) and the camera's state (index, calibration revision)"};
  std::string scene_file, config_file;
  std::string to = "rtp://127.0.0.1:5600";
  double seconds = 0.0;
  int bitrate_kbps = 4000;
  double key_interval_s = 0.5;
  auto* scene_opt =
      app.add_option("--scene", scene_file,
                     "scene file whose simulated cameras are sent (e.g. scenes/default.yaml)")
          ->check(CLI::ExistingFile);
  app.add_option("--config", config_file,
                 "remote.yaml: the site's real cameras by driver id (mock, /dev/videoN, a GigE "
                 "id), each with its calibration file and the station's rtp://HOST:PORT, codec "
                 "and rate settings, key file (example: remote/remote-example.yaml); the "
                 "--to/--bitrate/--key options are then the file's")
      ->excludes(scene_opt);
  app.add_option("--to", to,
                 "the station's address of camera 0, rtp://HOST:PORT; camera i goes to "
                 "PORT + 2 i (RTCP on the next port)")
      ->capture_default_str();
  app.add_option("--seconds", seconds, "stop after this long (0: until Ctrl-C)")
      ->capture_default_str();
  app.add_option("--bitrate-kbps", bitrate_kbps, "x264enc bitrate per camera")
      ->capture_default_str()
      ->check(CLI::Range(50, 100000));
  app.add_option("--key-interval-s", key_interval_s,
                 "a key frame (with SPS/PPS), or with --intra-refresh a refresh sweep, at least "
                 "this often: how soon a station that joins or loses packets shows video again")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 10.0));
  bool no_rtx = false;
  app.add_flag("--no-rtx", no_rtx,
               "answer no NACKs (no RTX, RFC 4588): a lost packet is then repaired only by the "
               "next key frame");
  int fec_percentage = 0;
  app.add_option("--fec", fec_percentage,
                 "ULP FEC (RFC 5109, rtpulpfecenc): this many % more packets, from which the "
                 "station rebuilds a lost packet without asking (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  bool intra_refresh = false;
  app.add_flag("--intra-refresh", intra_refresh,
               "x264enc intra refresh: no IDR after the first, even on a PLI; a column of intra "
               "blocks sweeps each picture once per --key-interval-s instead, so "
               "a loss heals by the end of the next whole sweep without a key frame's burst, if "
               "no other loss hits it (the station detects it from the stream's recovery points)");
  bool full_rate = false;
  app.add_flag("--full-rate", full_rate,
               "ignore the station's view feedback and send every camera at full rate (by "
               "default a camera the station says it cannot use soon is sent at 1/6 of its rate "
               "until it is needed, then resumes with a key frame)");
  std::string key_file;
  app.add_option("--key-file", key_file,
                 "pre-shared SRTP key (56 hex digits: AES-128-GCM key + salt), readable by its "
                 "owner only; media and RTCP are then encrypted and authenticated");
  std::string scene_epoch;
  app.add_option("--scene-epoch", scene_epoch,
                 "scene t = 0 as a CLOCK_REALTIME instant, seconds since 1970 (e.g. "
                 "$(date +%s.%N) + a few s); give the station the same, so the objects these "
                 "cameras see and the station's head follow one scene clock (default: this "
                 "program's start)");
  CLI11_PARSE(app, argc, argv);
  if (!config_file.empty()) {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    return hd::remote::run_config(config_file, seconds, g_stop);
  }
  if (scene_file.empty()) {
    std::fprintf(stderr, "hybrid-remote: give --scene FILE or --config FILE (see --help)\n");
    return 2;
  }

  std::string why;
  const auto address = hd::drivers::parse_rtp_uri(to, why);
  if (!address) {
    std::fprintf(stderr, "hybrid-remote: --to: %s\n", why.c_str());
    return 2;
  }
  std::optional<hd::drivers::SrtpKey> key;
  if (!key_file.empty()) {
    try {
      key = hd::drivers::read_srtp_key_file(key_file);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hybrid-remote: --key-file: %s\n", e.what());
      return 2;
    }
  }
  std::optional<int64_t> epoch_realtime_ns;
  if (!scene_epoch.empty()) {
    epoch_realtime_ns = hd::sim::parse_scene_epoch(scene_epoch, why);
    if (!epoch_realtime_ns) {
      std::fprintf(stderr, "hybrid-remote: --scene-epoch: %s\n", why.c_str());
      return 2;
    }
  }
  std::unique_ptr<hd::sim::Simulation> sim;
  try {
    sim = std::make_unique<hd::sim::Simulation>(hd::sim::load_scene(scene_file));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybrid-remote: %s\n", e.what());
    return 2;
  }

  std::vector<std::unique_ptr<hd::remote::RtpSender>> senders;
  std::printf("hybrid-remote: scene %s (%s), %zu cameras\n", scene_file.c_str(),
              sim->scene().name.c_str(), sim->camera_count());
  // p_c and P_c as the station would use them in scene mode (no distortion unless the scene
  // renders it): sent with every frame, so the station needs no calibration file.
  const std::vector<hd::drivers::CalibratedCamera> calibrated = sim->station_cameras();
  for (std::size_t i = 0; i < sim->camera_count(); ++i) {
    const hd::sim::SceneCamera& sc = sim->scene().cameras[i];
    hd::remote::RtpSendConfig c;
    c.host = address->host;
    c.port = static_cast<uint16_t>(address->port + 2 * i);
    c.width_px = static_cast<int>(sc.p_c.width);
    c.height_px = static_cast<int>(sc.p_c.height);
    c.rate_hz = sc.rate_hz;
    c.bitrate_kbps = bitrate_kbps;
    c.key_interval_s = key_interval_s;
    c.camera_index = static_cast<uint8_t>(i);
    c.calibration_revision = 1;  // the scene's calibration is fixed for the run
    c.p_c = calibrated[i].p_c;
    c.T_world_cam = calibrated[i].T_world_real;
    c.srtp_key = key;
    c.retransmission = !no_rtx;
    c.fec_percentage = fec_percentage;
    c.intra_refresh = intra_refresh;
    c.follow_view = !full_rate;
    std::unique_ptr<hd::remote::RtpSender> s;
    try {
      s = std::make_unique<hd::remote::RtpSender>(c);
      s->start();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hybrid-remote: camera %zu: %s\n", i, e.what());
      return 3;
    }
    std::printf(
        "  camera %zu %-10s %dx%d at %g Hz -> rtp://%s:%d (RTCP %d): x264enc (software; "
        "zerolatency, ultrafast, no B-frames, %s every %d frames, VBV %d ms = one frame, "
        "%d kbit/s), rtph264pay, rtpbin (%s%s); per packet: ntp-64 capture time (CLOCK_REALTIME: "
        "the "
        "station maps it exactly on one host, else as well as the hosts' clocks agree) and "
        "camera-state (index %zu, calibration revision %u); with every frame: p_c and P_c "
        "(calibration element, %zu bytes)\n",
        i, sc.name.c_str(), c.width_px, c.height_px, c.rate_hz, c.host.c_str(), c.port, c.port + 1,
        c.intra_refresh ? "intra refresh (no IDR after the first, a PLI starts a sweep): a sweep"
                        : "key frame",
        c.key_int_frames(), c.vbv_buffer_ms(), c.bitrate_kbps,
        c.retransmission ? ("RTX: NACKed packets of the last " + std::to_string(c.rtx_history_ms) +
                            " ms sent again, payload type " + std::to_string(c.rtx_payload_type))
                               .c_str()
                         : "no RTX",
        c.fec_percentage > 0 ? ("; ULP FEC +" + std::to_string(c.fec_percentage) +
                                " %, payload type " + std::to_string(c.fec_payload_type))
                                   .c_str()
                             : "; no FEC",
        i, c.calibration_revision, hd::drivers::calibration_element_size(c.p_c->distortion_count));
    senders.push_back(std::move(s));
  }
  std::printf("  security: %s\n",
              key ? ("SRTP AES-128-GCM on media and RTCP, key file " + key->file).c_str()
                  : "none: RTP in the clear (no --key-file)");
  if (epoch_realtime_ns) {
    const int64_t epoch_mono = hd::sim::realtime_to_monotonic_ns(*epoch_realtime_ns);
    sim->set_epoch_ns(epoch_mono);
    std::printf("  scene time: t = 0 at --scene-epoch %s (CLOCK_REALTIME), %+.3f s from now\n",
                scene_epoch.c_str(),
                1e-9 * static_cast<double>(epoch_mono - hd::drivers::monotonic_now_ns()));
  } else {
    std::printf("  scene time: t = 0 when the cameras start (no --scene-epoch)\n");
  }
  std::printf(
      "  calibration: the scene's p_c and P_c in the stream (the station needs no calibration "
      "file)\n");
  std::fflush(stdout);

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  sim->start();
  const int64_t start_ns = hd::drivers::monotonic_now_ns();
  while (!g_stop) {
    for (std::size_t i = 0; i < senders.size(); ++i) {
      auto& mailbox = sim->camera(i).frames();
      if (mailbox.fetch()) senders[i]->push(mailbox.latest());
    }
    if (seconds > 0 && hd::drivers::monotonic_now_ns() - start_ns > int64_t(seconds * 1e9)) break;
    // Polls the cameras' mailboxes (they have no wake-up); 0.5 ms adds at most that to latency.
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  sim->stop();
  for (std::size_t i = 0; i < senders.size(); ++i) {
    const hd::remote::RtpSenderStats st = senders[i]->stats();
    uint64_t malformed = 0;
    for (uint64_t m : st.view_feedback_malformed) malformed += m;
    std::printf(
        "  camera %zu: %llu frames taken, %llu refused, %llu stamped, %llu packets; RTX %llu "
        "requested, %llu sent; view feedback %llu received (%llu malformed, ignored), %llu frames "
        "not sent while not needed, %llu key frames forced on becoming needed\n",
        i, static_cast<unsigned long long>(st.frames_pushed),
        static_cast<unsigned long long>(st.frames_refused),
        static_cast<unsigned long long>(st.frames_stamped),
        static_cast<unsigned long long>(st.packets_stamped),
        static_cast<unsigned long long>(st.rtx_requests),
        static_cast<unsigned long long>(st.rtx_packets_sent),
        static_cast<unsigned long long>(st.view_feedback_received),
        static_cast<unsigned long long>(malformed),
        static_cast<unsigned long long>(st.frames_skipped_not_needed),
        static_cast<unsigned long long>(st.key_frames_forced));
    senders[i]->stop();
  }
  return 0;
}
