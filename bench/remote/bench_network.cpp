// hybrid-bench-network: the fair link benchmark. The same pre-rendered frames, held in memory,
// go through our link (RtpSender → UDP loopback → RtpCamera's mailbox) and through a plain
// GStreamer pipeline with the same caps, encoder settings and conversions (bench/remote/
// peer_link.h), both in this process, in interleaved segments (ours, peer, peer, ours, ...), each
// measured from the capture stamp to the decoded RGBA frame available to the consumer, with the
// process's CPU time per frame beside it. Cases: 1 and 2 cameras at 1280x720 60 Hz, and 3 at
// 640x480 30 Hz (the demo's).
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bench/remote/peer_link.h"
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

double cpu_s() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         double(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

struct Case {
  int cameras, width, height, fps;
  std::string name() const {
    return std::to_string(cameras) + " x " + std::to_string(width) + "x" + std::to_string(height) +
           " at " + std::to_string(fps) + " Hz";
  }
};

// One chain's figures over all its segments.
struct Figures {
  std::vector<double> ms;
  uint64_t in = 0, out = 0;
  double cpu_s = 0.0;
  // Ours: capture → encoded → sent → received → decoded → in the mailbox; the peer: capture →
  // encoded → received → decoded → available (its stage 4 stays empty).
  std::vector<double> stage_ms[5];
  double cpu_ms_per_frame() const { return in > 0 ? cpu_s * 1e3 / double(in) : 0.0; }
};

struct CaseResult {
  Case c;
  Figures ours, peer;
};

enum class Active { kNone, kOurs, kPeer };

CaseResult run_case(const Case& c, double seconds, double segment_s, int bitrate_kbps) {
  std::vector<std::unique_ptr<hd::drivers::RtpCamera>> cams;
  std::vector<std::unique_ptr<hd::remote::RtpSender>> senders;
  std::vector<std::unique_ptr<hd::bench::PeerLink>> peers;
  for (int i = 0; i < c.cameras; ++i) {
    const uint16_t port = free_port();
    hd::drivers::RtpReceiveConfig rc;
    rc.listen = {"127.0.0.1", port};
    cams.push_back(std::make_unique<hd::drivers::RtpCamera>(rc));
    cams.back()->negotiate({c.width, c.height, {}, 0.0});
    cams.back()->start();
    hd::remote::RtpSendConfig sc;
    sc.port = port;
    sc.width_px = c.width;
    sc.height_px = c.height;
    sc.rate_hz = c.fps;
    sc.bitrate_kbps = bitrate_kbps;
    sc.camera_index = static_cast<uint8_t>(i);
    senders.push_back(std::make_unique<hd::remote::RtpSender>(sc));
    senders.back()->start();
    peers.push_back(std::make_unique<hd::bench::PeerLink>(
        hd::bench::PeerLinkConfig{c.width, c.height, c.fps, bitrate_kbps, free_port()}));
  }
  // Drawn before the run and shared by both chains: the "camera" costs what a driver's
  // hand-over costs, the same for both.
  std::vector<std::vector<hd::drivers::Frame>> drawn(c.cameras);
  for (int i = 0; i < c.cameras; ++i) {
    drawn[i].resize(kDrawnFrames);
    for (std::size_t n = 0; n < kDrawnFrames; ++n) {
      drawn[i][n].allocate_rgba(c.width, c.height);
      draw(drawn[i][n], n, i);
    }
  }
  std::atomic<Active> active{Active::kNone};
  std::atomic<bool> stop{false};
  std::atomic<uint64_t> pushed{0};
  std::vector<std::thread> feeders;
  for (int i = 0; i < c.cameras; ++i)
    feeders.emplace_back([&, i] {
      const auto period = std::chrono::nanoseconds(1'000'000'000 / c.fps);
      auto next = std::chrono::steady_clock::now();
      for (uint64_t n = 0; !stop; ++n) {
        hd::drivers::Frame& f = drawn[i][n % kDrawnFrames];
        const int64_t now = monotonic_now_ns();  // "captured" now
        const Active a = active.load();
        if (a == Active::kOurs) {
          f.host_timestamp_ns = now;
          f.sequence = n;
          senders[i]->push(f);
        } else if (a == Active::kPeer) {
          peers[i]->push(f, now);
        }
        if (a != Active::kNone) pushed.fetch_add(1);
        next += period;
        std::this_thread::sleep_until(next);
      }
    });
  CaseResult r{c, {}, {}};
  auto drain_ours = [&](Figures* into) {
    hd::drivers::RtpFrameTiming t;
    for (auto& cam : cams)
      while (cam->pop_timing(t)) {
        if (into == nullptr || !t.stamped) continue;
        ++into->out;
        into->ms.push_back((t.published_ns - t.capture_ns) * 1e-6);
        const int64_t at[6] = {t.capture_ns,  t.encoded_ns, t.sent_ns,
                               t.received_ns, t.decoded_ns, t.published_ns};
        for (int k = 0; k < 5; ++k)
          if (at[k] != 0 && at[k + 1] != 0) into->stage_ms[k].push_back((at[k + 1] - at[k]) * 1e-6);
      }
  };
  auto drain_peer = [&](Figures* into) {
    for (auto& p : peers)
      for (const hd::bench::PeerFrameTiming& t : p->take_timings()) {
        if (into == nullptr) continue;
        ++into->out;
        into->ms.push_back((t.available_ns - t.capture_ns) * 1e-6);
        const int64_t at[5] = {t.capture_ns, t.encoded_ns, t.received_ns, t.decoded_ns,
                               t.available_ns};
        for (int k = 0; k < 4; ++k)
          if (at[k] != 0 && at[k + 1] != 0) into->stage_ms[k].push_back((at[k + 1] - at[k]) * 1e-6);
      }
  };
  const int rounds = std::max(1, static_cast<int>(std::lround(seconds / segment_s)));
  for (int round = 0; round < rounds; ++round) {
    for (int k = 0; k < 2; ++k) {
      const bool ours = (k == 0) == (round % 2 == 0);  // ours, peer, peer, ours, ...
      active = ours ? Active::kOurs : Active::kPeer;
      // Warm-up: the chain's first frames after its pause (a key frame asked for, the jitter
      // buffer's resync) are not measured.
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
      drain_ours(nullptr);
      drain_peer(nullptr);
      Figures& f = ours ? r.ours : r.peer;
      const uint64_t pushed0 = pushed.load();
      const double cpu0 = cpu_s();
      const int64_t start = monotonic_now_ns();
      while (monotonic_now_ns() - start < int64_t(segment_s * 1e9)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        if (ours) drain_ours(&f);
      }
      active = Active::kNone;
      // Frames still in the link count as this segment's (a frame period or two).
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      f.cpu_s += cpu_s() - cpu0;
      f.in += pushed.load() - pushed0;
      if (ours)
        drain_ours(&f);
      else
        drain_peer(&f);
      std::fprintf(stderr, "\r%s: round %d of %d", c.name().c_str(), round + 1, rounds);
    }
  }
  std::fprintf(stderr, "\n");
  stop = true;
  for (auto& t : feeders) t.join();
  for (auto& s : senders) s->stop();
  for (auto& cam : cams) cam->stop();
  return r;
}

void print_case(const CaseResult& r) {
  std::printf("\n%s, interleaved segments\n", r.c.name().c_str());
  std::printf(
      "| chain | frames in | frames out | p50 ms | p95 ms | p99 ms | CPU ms per frame |\n"
      "|---|---|---|---|---|---|---|\n");
  auto row = [](const char* what, const Figures& f) {
    std::printf("| %s | %llu | %llu | %.2f | %.2f | %.2f | %.2f |\n", what,
                static_cast<unsigned long long>(f.in), static_cast<unsigned long long>(f.out),
                percentile(f.ms, 0.5), percentile(f.ms, 0.95), percentile(f.ms, 0.99),
                f.cpu_ms_per_frame());
  };
  row("ours: RtpSender -> RtpCamera mailbox", r.ours);
  row("peer: GStreamer pipeline -> appsink", r.peer);
  const auto& s = r.ours.stage_ms;
  std::printf(
      "ours stage by stage, p50 ms: capture -%.2f- encoded -%.2f- sent -%.2f- received -%.2f- "
      "decoded -%.2f- in the mailbox\n",
      percentile(s[0], 0.5), percentile(s[1], 0.5), percentile(s[2], 0.5), percentile(s[3], 0.5),
      percentile(s[4], 0.5));
  const auto& q = r.peer.stage_ms;
  std::printf(
      "peer stage by stage, p50 ms: capture -%.2f- encoded -%.2f- received -%.2f- decoded "
      "-%.2f- available\n",
      percentile(q[0], 0.5), percentile(q[1], 0.5), percentile(q[2], 0.5), percentile(q[3], 0.5));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-network: the fair link benchmark, ours (RtpSender -> UDP -> RtpCamera) "
      "beside a plain GStreamer pipeline with the same caps and encoder settings"};
  app.footer(
      "Both chains run in this process on the same pre-rendered RGBA frames, in interleaved "
      "segments (ours, peer, peer, ours, ...), each measured from the capture stamp to the "
      "decoded RGBA frame available to the consumer (ours: published in the camera's mailbox; "
      "peer: the appsink's callback), with the process's CPU time per frame pushed. Run it on an "
      "idle machine and quote the ratios:\n"
      "  build/bin/hybrid-bench-network --seconds 12");
  double seconds = 12.0, segment_s = 2.0;
  int bitrate_kbps = 4000;
  std::string which = "all";
  app.add_option("--seconds", seconds, "measured time per chain and case")->capture_default_str();
  app.add_option("--segment-s", segment_s, "length of one measured segment")->capture_default_str();
  app.add_option("--bitrate-kbps", bitrate_kbps)->capture_default_str();
  app.add_option("--case", which, "all, 1x720p60, 2x720p60 or 3x480p30")
      ->capture_default_str()
      ->check(CLI::IsMember({"all", "1x720p60", "2x720p60", "3x480p30"}));
  CLI11_PARSE(app, argc, argv);

  const std::vector<std::pair<std::string, Case>> all{{"1x720p60", {1, 1280, 720, 60}},
                                                      {"2x720p60", {2, 1280, 720, 60}},
                                                      {"3x480p30", {3, 640, 480, 30}}};
  std::vector<CaseResult> results;
  for (const auto& [name, c] : all)
    if (which == "all" || which == name) {
      results.push_back(run_case(c, seconds, segment_s, bitrate_kbps));
      print_case(results.back());
    }
  std::printf(
      "\n%d kbit/s each, x264enc (zerolatency, ultrafast), loopback, %.0f s per chain and case in "
      "%.1f s segments\n| case | ours p50 ms | peer p50 ms | ours / peer | ours CPU ms/frame | "
      "peer CPU ms/frame | CPU ours / peer |\n|---|---|---|---|---|---|---|\n",
      bitrate_kbps, seconds, segment_s);
  for (const CaseResult& r : results) {
    const double o = percentile(r.ours.ms, 0.5), p = percentile(r.peer.ms, 0.5);
    const double oc = r.ours.cpu_ms_per_frame(), pc = r.peer.cpu_ms_per_frame();
    std::printf("| %s | %.1f | %.1f | %.2f | %.2f | %.2f | %.2f |\n", r.c.name().c_str(), o, p,
                p > 0 ? o / p : 0.0, oc, pc, pc > 0 ? oc / pc : 0.0);
  }
  return 0;
}
