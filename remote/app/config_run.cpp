#include "remote/app/config_run.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "calib/replay_images.h"
#include "core/config/config_error.h"
#include "drivers/camera_factory.h"
#include "drivers/camera_format.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/srtp_key.h"
#include "remote/app/remote_config.h"
#include "remote/sender/h264_encoder.h"
#include "remote/sender/rtp_sender.h"

namespace hd::remote {

int run_config(const std::string& config_file, double seconds, const std::atomic<bool>& stop) {
  RemoteConfig config;
  try {
    config = load_remote_config(config_file);
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "hybrid-remote: %s\n", e.what());
    return 2;
  }
  std::optional<drivers::SrtpKey> key;
  if (!config.key_file.empty()) key = drivers::read_srtp_key_file(config.key_file);  // checked

  H264EncoderChoice encoder;
  try {
    encoder = choose_h264_encoder(config.encoder);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybrid-remote: %s: %s\n", config_file.c_str(), e.what());
    return 3;
  }
  std::printf("hybrid-remote: config %s, %zu cameras\n", config_file.c_str(),
              config.cameras.size());
  std::printf("  encoder: %s (%s%s%s)\n", encoder.element.c_str(),
              encoder.hardware ? "hardware" : "software",
              encoder.why_not_others.empty() ? "" : "; no hardware H.264 encoder works here: ",
              encoder.why_not_others.c_str());

  std::vector<std::unique_ptr<drivers::CameraSource>> cameras;
  std::vector<std::unique_ptr<RtpSender>> senders;
  for (std::size_t i = 0; i < config.cameras.size(); ++i) {
    const RemoteCameraConfig& cc = config.cameras[i];
    const std::string label = cc.name + " (" + cc.id + ")";
    std::unique_ptr<drivers::CameraSource> cam;
    drivers::FormatNegotiation got;
    const drivers::CameraFormatRequest want{cc.p_c.width, cc.p_c.height, {}, cc.rate_hz};
    try {
      cam = drivers::make_camera_source(cc.id, calib::load_replay_images);
      got = cam->negotiate(want);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hybrid-remote: camera %s: MISSING: %s\n", label.c_str(), e.what());
      return 3;
    }
    const drivers::FormatVerdict verdict = drivers::judge_format(want, got);
    if (!verdict.ok) {
      std::fprintf(stderr, "hybrid-remote: camera %s: calibrated at %s (%s), but the camera %s\n",
                   label.c_str(), drivers::size_text(cc.p_c.width, cc.p_c.height).c_str(),
                   cc.calibration_file.c_str(), verdict.problem.c_str());
      return 3;
    }
    RtpSendConfig sc;
    sc.host = cc.to.host;
    sc.port = cc.to.port;
    sc.width_px = cc.p_c.width;
    sc.height_px = cc.p_c.height;
    sc.rate_hz = cc.rate_hz;
    sc.bitrate_kbps = cc.bitrate_kbps;
    sc.key_interval_s = cc.key_interval_s;
    sc.intra_refresh = cc.intra_refresh;
    sc.encoder = encoder.element;
    sc.camera_index = static_cast<uint8_t>(i);
    sc.calibration_revision = 1;  // the file's, fixed for the run
    sc.p_c = cc.p_c;
    sc.T_world_cam = cc.T_world_cam;
    sc.srtp_key = key;
    auto sender = std::make_unique<RtpSender>(sc);
    try {
      sender->start();
      cam->start();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hybrid-remote: camera %s: %s\n", label.c_str(), e.what());
      return 3;
    }
    const Eigen::Vector3d& c = cc.T_world_cam.t;
    std::printf(
        "  camera %zu %-10s %s: %s -> rtp://%s:%d (RTCP %d): %s %d kbit/s, %s every %d "
        "frames, at %g Hz; calibration: from file %s (revision 1, sent with every frame in the "
        "calibration element, %zu bytes), centre (%.2f, %.2f, %.2f) m\n",
        i, cc.name.c_str(), cc.id.c_str(),
        got.delivered.known() ? drivers::format_text(got.delivered).c_str()
                              : drivers::size_text(cc.p_c.width, cc.p_c.height).c_str(),
        sc.host.c_str(), sc.port, sc.port + 1, sc.encoder.c_str(), sc.bitrate_kbps,
        sc.intra_refresh ? "intra refresh (no IDR after the first, a PLI starts a sweep): a sweep"
                         : "key frame",
        sc.key_int_frames(), sc.rate_hz, cc.calibration_file.c_str(),
        drivers::calibration_element_size(cc.p_c.distortion_count), c.x(), c.y(), c.z());
    cameras.push_back(std::move(cam));
    senders.push_back(std::move(sender));
  }
  std::printf(
      "  per packet: ntp-64 capture time (CLOCK_REALTIME) and camera-state (index, "
      "calibration revision)\n");
  std::printf("  security: %s\n",
              key ? ("SRTP AES-128-GCM on media and RTCP, key file " + key->file).c_str()
                  : "none: RTP in the clear (no key_file)");
  std::fflush(stdout);

  const int64_t start_ns = drivers::monotonic_now_ns();
  while (!stop) {
    for (std::size_t i = 0; i < senders.size(); ++i) {
      auto& mailbox = cameras[i]->frames();
      if (mailbox.fetch()) senders[i]->push(mailbox.latest());
    }
    if (seconds > 0 && drivers::monotonic_now_ns() - start_ns > int64_t(seconds * 1e9)) break;
    // The drivers' mailboxes have no wake-up; 0.5 ms adds at most that to the latency.
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  for (std::size_t i = 0; i < senders.size(); ++i) {
    cameras[i]->stop();
    const RtpSenderStats st = senders[i]->stats();
    std::printf(
        "  camera %zu: %llu frames sent, %llu refused, %llu with calibration, %llu "
        "packets\n",
        i, static_cast<unsigned long long>(st.frames_pushed),
        static_cast<unsigned long long>(st.frames_refused),
        static_cast<unsigned long long>(st.packets_with_calibration),
        static_cast<unsigned long long>(st.packets_stamped));
    senders[i]->stop();
  }
  cameras.clear();
  drivers::shutdown_camera_drivers();
  return 0;
}

}  // namespace hd::remote
