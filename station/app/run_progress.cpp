#include "station/app/run_progress.h"

#include <unistd.h>

#include <cinttypes>
#include <cmath>

namespace hd::station {

RunProgress::RunProgress(double period_s, std::FILE* out, int64_t start_ns)
    : period_ns_(period_s > 0.0 ? static_cast<int64_t>(std::llround(period_s * 1e9)) : 0),
      out_(out),
      start_ns_(start_ns),
      next_ns_(start_ns + period_ns_) {}

void RunProgress::frame_done(core::Variant variant, uint64_t frames, uint64_t missed,
                             int64_t now_ns) {
  ++variants_[static_cast<int>(variant)];
  if (period_ns_ == 0 || now_ns < next_ns_) return;
  next_ns_ += period_ns_ * ((now_ns - next_ns_) / period_ns_ + 1);  // no burst after a stall
  const double pct = frames ? 100.0 * static_cast<double>(missed) / static_cast<double>(frames) : 0;
  const long rss = resident_kib();
  std::fprintf(out_,
               "  [%6.0f s] frames %" PRIu64 ", missed deadlines %" PRIu64
               " (%.2f %%); video %" PRIu64 " / hybrid %" PRIu64 " / synthetic %" PRIu64
               " frames; resident %.1f MiB",
               1e-9 * static_cast<double>(now_ns - start_ns_), frames, missed, pct, variants_[0],
               variants_[1], variants_[2], rss >= 0 ? static_cast<double>(rss) / 1024.0 : NAN);
  if (have_model_)
    std::fprintf(out_, "; model updates %" PRIu64 ", stereo reconstructions %" PRIu64,
                 model_updates_, reconstructions_);
  std::fputc('\n', out_);
  std::fflush(out_);
}

long RunProgress::resident_kib() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  long size = 0, resident = -1;
  const int n = std::fscanf(f, "%ld %ld", &size, &resident);
  std::fclose(f);
  if (n != 2 || resident < 0) return -1;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

}  // namespace hd::station
