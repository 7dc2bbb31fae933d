// hybrid-bench-gige: how much latency the GigE driver adds between a frame's arrival (Aravis's
// stream thread completed it) and its publication in the mailbox, and whether the hand-off
// allocates. Peers measured in the same run: Aravis's own output-queue hand-off (arrival -> our
// pop) and a plain memcpy of one RGBA frame of the same size.
#include <arv.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>
#include <vector>

#include "core/allocation_counter.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/gige/gige_camera.h"
#include "fake_gige_camera.h"

namespace {

struct Percentiles {
  double p50, p95, p99, max;
};

Percentiles percentiles_us(std::vector<int64_t> ns) {
  if (ns.empty()) return {0, 0, 0, 0};
  std::sort(ns.begin(), ns.end());
  const auto at = [&](double q) {
    return ns[std::min(ns.size() - 1,
                       static_cast<std::size_t>(q * static_cast<double>(ns.size())))] /
           1000.0;
  };
  return {at(0.50), at(0.95), at(0.99), ns.back() / 1000.0};
}

void print_row(const char* name, const Percentiles& p, std::size_t n) {
  std::printf("  %-48s %9.1f %9.1f %9.1f %9.1f   (n=%zu)\n", name, p.p50, p.p95, p.p99, p.max, n);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"GigE frame hand-off latency against Aravis's fake GigE camera on 127.0.0.1"};
  int width = 640, height = 480;
  double fps = 60.0, seconds = 10.0;
  std::string format = "Mono8";
  app.add_option("--width", width, "image width (px)");
  app.add_option("--height", height, "image height (px)");
  app.add_option("--fps", fps, "frame rate (Hz)");
  app.add_option("--seconds", seconds, "measurement time after 1 s warm-up");
  app.add_option("--format", format, "Mono8, RGB8, BayerRG8, BayerGR8, BayerGB8, BayerBG8");
  CLI11_PARSE(app, argc, argv);

  using hd::drivers::PixelFormat;
  PixelFormat pf = PixelFormat::kMono8;
  for (PixelFormat f :
       {PixelFormat::kMono8, PixelFormat::kRgb8, PixelFormat::kBayerRggb8, PixelFormat::kBayerGrbg8,
        PixelFormat::kBayerGbrg8, PixelFormat::kBayerBggr8})
    if (hd::drivers::to_string(f) == format) pf = f;

  hd::drivers::testing::FakeGigeCamera fake;
  hd::drivers::GigeConfig cfg;
  cfg.device_id = "Aravis-Fake-SERIAL";
  cfg.pixel_format = pf;
  cfg.roi = {0, 0, width, height};
  cfg.frame_rate_hz = fps;
  hd::drivers::GigeCamera cam(cfg);
  try {
    cam.start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hybrid-bench-gige: %s\n", e.what());
    return 1;
  }

  hd::drivers::GigeHandoffTiming t;
  std::vector<int64_t> total, aravis, ours;
  total.reserve(100000);
  aravis.reserve(100000);
  ours.reserve(100000);
  uint64_t consumer_fetches = 0, consumer_allocs = 0, process_allocs = 0;
  const auto drain = [&](bool keep) {
    while (cam.pop_timing(t))
      if (keep) {
        total.push_back(t.published_ns - t.arrival_ns);
        aravis.push_back(t.popped_ns - t.arrival_ns);
        ours.push_back(t.published_ns - t.popped_ns);
      }
  };
  const auto warm_end = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (std::chrono::steady_clock::now() < warm_end) {
    cam.frames().fetch();
    drain(false);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto dropped_before = cam.dropped_frames();
  // Every thread's allocations count from here: Aravis's stream thread and ours as well.
  hd::core::count_allocations_on_all_threads(true);
  const uint64_t process_before = hd::core::counted_allocations();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  uint64_t checksum = 0;
  while (std::chrono::steady_clock::now() < end) {
    // The consumer side of the hand-off, as the render loop does it: fetch and read.
    const uint64_t before = hd::core::counted_allocations_on_this_thread();
    if (cam.frames().fetch()) {
      ++consumer_fetches;
      checksum += cam.frames().latest().data[0];
    }
    consumer_allocs += hd::core::counted_allocations_on_this_thread() - before;
    drain(true);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  process_allocs = hd::core::counted_allocations() - process_before;
  hd::core::count_allocations_on_all_threads(false);
  const auto published = cam.stats().frames_published;
  const auto dropped = cam.dropped_frames() - dropped_before;
  cam.stop();

  // Peer: copying one RGBA frame of this size, timed here on the same machine.
  const std::size_t bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4;
  std::vector<uint8_t> a(bytes, 1), b(bytes, 0);
  std::vector<int64_t> copy_ns;
  for (int i = 0; i < 200; ++i) {
    const int64_t t0 = hd::drivers::monotonic_now_ns();
    std::memcpy(b.data(), a.data(), bytes);
    copy_ns.push_back(hd::drivers::monotonic_now_ns() - t0);
    a[static_cast<std::size_t>(i) % bytes] = b[bytes - 1 - static_cast<std::size_t>(i)];
  }

  std::printf("hybrid-bench-gige: %dx%d %s at %.1f fps for %.1f s (fake GigE camera, 127.0.0.1)\n",
              width, height, format.c_str(), cam.frame_rate_hz(), seconds);
  std::printf("  packet size %d B, socket buffer %d B, payload %zu B\n", cam.packet_size_bytes(),
              cam.socket_buffer_bytes(), cam.payload_bytes());
  std::printf("  %-48s %9s %9s %9s %9s\n", "latency (us)", "p50", "p95", "p99", "max");
  // Aravis stamps a buffer's system time when the frame's first packet lands, so "arrival ->
  // popped" holds the frame's own transfer time as well as Aravis's queue hand-off.
  print_row("arrival -> mailbox (total)", percentiles_us(total), total.size());
  print_row("  arrival -> popped (Aravis: wire + queue, peer)", percentiles_us(aravis),
            aravis.size());
  print_row("  popped -> published (driver: convert+publish)", percentiles_us(ours), ours.size());
  print_row("memcpy of one RGBA frame (peer)", percentiles_us(copy_ns), copy_ns.size());
  std::printf("  frames published %llu, dropped %llu, consumer fetches %llu\n",
              static_cast<unsigned long long>(published), static_cast<unsigned long long>(dropped),
              static_cast<unsigned long long>(consumer_fetches));
  std::printf(
      "  C++ heap allocations: consumer fetch+read %llu; whole process while streaming %llu\n",
      static_cast<unsigned long long>(consumer_allocs),
      static_cast<unsigned long long>(process_allocs));
  std::printf("  (checksum %llu)\n", static_cast<unsigned long long>(checksum));
  return 0;
}
