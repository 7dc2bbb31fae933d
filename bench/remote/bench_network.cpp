// hybrid-bench-network: two cameras at 1280x720 and 60 fps over loopback through the real path
// (RtpSender → UDP → RtpCamera), link-added latency (sender capture → decoded frame in the
// station's mailbox) p50/p95/p99 and bytes per second, beside the same encode/send/receive/decode
// chain built with gst-launch-1.0 in the same run (two pipelines, both ends in each, measured by
// GStreamer's latency tracer from videotestsrc to the sink).
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_sender.h"

namespace {

using hd::drivers::monotonic_now_ns;

constexpr std::size_t kDrawnFrames = 30;  // half a second of motion at 60 fps, repeated

uint16_t free_port() {
  for (int attempt = 0; attempt < 64; ++attempt) {
    int s = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
    ::close(s);
    const uint16_t p = static_cast<uint16_t>(ntohs(a.sin_port) & ~1u);
    if (p >= 1024 && p < 65000) return p;
  }
  return 0;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

void print_row(const char* what, const std::vector<double>& ms, double bytes_per_s) {
  std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.0f |\n", what, ms.size(), percentile(ms, 0.5),
              percentile(ms, 0.95), percentile(ms, 0.99), bytes_per_s);
}

// A moving test image: a bright bar sweeping over a gradient, rewritten in place each frame.
void draw(hd::drivers::Frame& f, uint64_t n, int camera) {
  const int bar = static_cast<int>((n * 8 + camera * 300) % f.width);
  for (int y = 0; y < f.height; ++y) {
    uint8_t* row = f.data.data() + std::size_t(y) * f.stride_bytes;
    for (int x = 0; x < f.width; ++x) {
      const bool in_bar = x >= bar && x < bar + 40;
      row[4 * x + 0] = in_bar ? 250 : static_cast<uint8_t>(x / 5);
      row[4 * x + 1] = in_bar ? 250 : static_cast<uint8_t>(y / 3);
      row[4 * x + 2] = static_cast<uint8_t>((x + y) / 8);
      row[4 * x + 3] = 255;
    }
  }
}

// The peer: gst-launch-1.0 with both ends in one pipeline and the latency tracer on; returns the
// latencies (ms) it logged for each half: the tracer measures from a source to a sink, and the
// UDP hop splits the pipeline into videotestsrc → udpsink (convert, encode, payload) and
// udpsrc → fakesink (jitter buffer, depayload, decode, convert).
struct PeerHalves {
  std::vector<double> send_ms, receive_ms;
};
PeerHalves run_peer(int cameras, double seconds, int width, int height, int fps, int bitrate_kbps,
                    const std::string& log_dir) {
  std::vector<pid_t> pids;
  std::vector<std::string> logs;
  for (int i = 0; i < cameras; ++i) {
    const uint16_t port = free_port();
    const std::string log = log_dir + "/peer" + std::to_string(i) + ".log";
    logs.push_back(log);
    const std::string caps =
        "application/x-rtp,media=video,clock-rate=90000,encoding-name=H264,payload=96";
    const std::string pipeline =
        "videotestsrc is-live=true pattern=ball ! video/x-raw,format=RGBA,width=" +
        std::to_string(width) + ",height=" + std::to_string(height) +
        ",framerate=" + std::to_string(fps) +
        "/1 ! videoconvert ! video/x-raw,format=I420 ! x264enc tune=zerolatency "
        "speed-preset=ultrafast bframes=0 key-int-max=" +
        std::to_string(fps / 2) + " vbv-buf-capacity=" + std::to_string((1000 + fps - 1) / fps) +
        " bitrate=" + std::to_string(bitrate_kbps) +
        " ! rtph264pay config-interval=-1 mtu=1200 ! udpsink host=127.0.0.1 port=" +
        std::to_string(port) +
        " sync=false async=false udpsrc address=127.0.0.1 port=" + std::to_string(port) +
        " caps=" + caps +
        " ! rtpjitterbuffer latency=20 ! rtph264depay ! avdec_h264 max-threads=1 ! videoconvert "
        "! video/x-raw,format=RGBA ! fakesink sync=false";
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::setenv("GST_TRACERS", "latency", 1);
      ::setenv("GST_DEBUG", "GST_TRACER:7", 1);
      ::setenv("GST_DEBUG_FILE", log.c_str(), 1);
      ::setenv("GST_DEBUG_NO_COLOR", "1", 1);
      std::vector<std::string> words{"gst-launch-1.0", "-q"};
      std::string w;
      for (char c : pipeline) {
        if (c == ' ') {
          if (!w.empty()) words.push_back(w);
          w.clear();
        } else {
          w += c;
        }
      }
      if (!w.empty()) words.push_back(w);
      std::vector<char*> argv;
      for (std::string& s : words) argv.push_back(s.data());
      argv.push_back(nullptr);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::execvp(argv[0], argv.data());
      ::_exit(127);
    }
    pids.push_back(pid);
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));  // the measured span
  for (pid_t p : pids) {
    ::kill(p, SIGINT);
    int status = 0;
    ::waitpid(p, &status, 0);
  }
  PeerHalves h;
  for (const std::string& log : logs) {
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);) {
      if (line.find("latency, src-element-id") == std::string::npos) continue;
      const std::size_t at = line.find("time=(guint64)");
      if (at == std::string::npos) continue;
      const char* text = line.c_str() + at + 14;
      char* end = nullptr;
      const double ns = std::strtod(text, &end);
      if (end == text) continue;  // a line cut short by the kill
      const double ms = ns * 1e-6;
      if (line.find("src-element=(string)videotestsrc") != std::string::npos)
        h.send_ms.push_back(ms);
      else if (line.find("src-element=(string)udpsrc") != std::string::npos)
        h.receive_ms.push_back(ms);
    }
  }
  return h;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-network: link-added latency and bytes/s of the network hop beside a "
      "gst-launch-1.0 peer"};
  double seconds = 10.0;
  int cameras = 2, width = 1280, height = 720, fps = 60, bitrate_kbps = 4000;
  app.add_option("--seconds", seconds, "measured span per chain")->capture_default_str();
  app.add_option("--cameras", cameras)->capture_default_str();
  app.add_option("--width", width)->capture_default_str();
  app.add_option("--height", height)->capture_default_str();
  app.add_option("--fps", fps)->capture_default_str();
  app.add_option("--bitrate-kbps", bitrate_kbps)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::vector<std::unique_ptr<hd::drivers::RtpCamera>> cams;
  std::vector<std::unique_ptr<hd::remote::RtpSender>> senders;
  for (int i = 0; i < cameras; ++i) {
    const uint16_t port = free_port();
    hd::drivers::RtpReceiveConfig rc;
    rc.listen = {"127.0.0.1", port};
    cams.push_back(std::make_unique<hd::drivers::RtpCamera>(rc));
    cams.back()->negotiate({width, height, {}, 0.0});
    cams.back()->start();
    hd::remote::RtpSendConfig sc;
    sc.port = port;
    sc.width_px = width;
    sc.height_px = height;
    sc.rate_hz = fps;
    sc.bitrate_kbps = bitrate_kbps;
    sc.camera_index = static_cast<uint8_t>(i);
    senders.push_back(std::make_unique<hd::remote::RtpSender>(sc));
    senders.back()->start();
  }
  std::atomic<bool> stop{false};
  std::vector<std::thread> feeders;
  for (int i = 0; i < cameras; ++i)
    feeders.emplace_back([&, i] {
      // Drawn before the run, so the "camera" costs what a driver's hand-over costs (the peer's
      // videotestsrc is cheap too): the chain measured is the link's.
      std::vector<hd::drivers::Frame> drawn(kDrawnFrames);
      for (std::size_t n = 0; n < drawn.size(); ++n) {
        drawn[n].allocate_rgba(width, height);
        draw(drawn[n], n, i);
      }
      const auto period = std::chrono::nanoseconds(1'000'000'000 / fps);
      auto next = std::chrono::steady_clock::now();
      for (uint64_t n = 0; !stop; ++n) {
        hd::drivers::Frame& f = drawn[n % drawn.size()];
        f.host_timestamp_ns = monotonic_now_ns();  // "captured" now
        f.sequence = n;
        senders[i]->push(f);
        next += period;
        std::this_thread::sleep_until(next);
      }
    });
  // Warm-up (encoders start, first key frames), then the measured span.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  hd::drivers::RtpFrameTiming t;
  for (auto& c : cams)
    while (c->pop_timing(t)) {
    }
  std::vector<uint64_t> bytes0;
  for (auto& c : cams) bytes0.push_back(c->stats().bytes);
  std::vector<double> ms;
  uint64_t unstamped = 0;
  const int64_t start = monotonic_now_ns();
  while (monotonic_now_ns() - start < int64_t(seconds * 1e9)) {
    for (auto& c : cams)
      while (c->pop_timing(t)) {
        if (!t.stamped) {
          ++unstamped;
          continue;
        }
        ms.push_back((t.published_ns - t.capture_ns) * 1e-6);
      }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const double span_s = (monotonic_now_ns() - start) * 1e-9;
  double bytes = 0;
  for (std::size_t i = 0; i < cams.size(); ++i) bytes += double(cams[i]->stats().bytes - bytes0[i]);
  stop = true;
  for (auto& f : feeders) f.join();
  for (auto& s : senders) s->stop();
  for (auto& c : cams) c->stop();

  char dir_template[] = "/tmp/hybrid-bench-network-XXXXXX";
  const char* dir = ::mkdtemp(dir_template);
  const PeerHalves peer =
      run_peer(cameras, seconds + 1.0, width, height, fps, bitrate_kbps, dir ? dir : "/tmp");

  std::printf("%d cameras %dx%d at %d fps, %d kbit/s each, loopback, %.1f s measured\n", cameras,
              width, height, fps, bitrate_kbps, span_s);
  std::printf(
      "| chain | frames | p50 ms | p95 ms | p99 ms | bytes/s |\n|---|---|---|---|---|---|\n");
  print_row("hybrid-remote sender -> RtpCamera mailbox (capture -> mailbox)", ms, bytes / span_s);
  print_row("peer gst-launch-1.0, latency tracer: videotestsrc -> udpsink", peer.send_ms, 0.0);
  print_row("peer gst-launch-1.0, latency tracer: udpsrc -> fakesink", peer.receive_ms, 0.0);
  if (unstamped > 0)
    std::printf("(%llu frames without a capture stamp left out)\n",
                static_cast<unsigned long long>(unstamped));
  const double peer_p50 = percentile(peer.send_ms, 0.5) + percentile(peer.receive_ms, 0.5);
  if (peer_p50 > 0 && !ms.empty())
    std::printf("peer p50 (sum of its halves' p50) %.2f ms; ours / peer %.2f\n", peer_p50,
                percentile(ms, 0.5) / peer_p50);
  return 0;
}
