#pragma once
// Per-frame latency log of the station: distributions, a CSV, a HUD line and a plot.

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "render/latency/latency_record.h"

namespace hd::render {

/// Order statistics of one metric, milliseconds. Percentiles are nearest-rank: the value at
/// sorted index ceil(p/100 * n) - 1.
struct LatencyStats {
  std::size_t count = 0;
  double p50_ms = 0, p95_ms = 0, p99_ms = 0, max_ms = 0, mean_ms = 0;
};

/// Keeps the newest `capacity` records in storage allocated at construction: record() and
/// hud_line() never allocate. Older records are overwritten (counted in overwritten()).
class LatencyRecorder {
 public:
  explicit LatencyRecorder(std::size_t capacity);

  void record(const LatencyRecord& r);
  std::size_t size() const { return count_; }
  uint64_t total_recorded() const { return total_; }
  uint64_t overwritten() const { return total_ - count_; }
  uint64_t missed_deadlines() const { return missed_; }
  /// i = 0 is the oldest kept record.
  const LatencyRecord& at(std::size_t i) const {
    return records_[(next_ + records_.size() - count_ + i) % records_.size()];
  }

  /// Over every kept record (sorts a preallocated scratch copy: no allocation).
  LatencyStats stats(LatencyMetric m) const;

  /// One line for the window's HUD: the newest frame's latencies and p95 over the last 128
  /// frames. Formatted into a member buffer; valid until the next call.
  std::string_view hud_line() const;

  /// CSV with a header row, one row per kept record; written to a temp file and renamed.
  /// Throws std::runtime_error naming the file on failure.
  void write_csv(const std::string& path) const;
  /// Reads what write_csv wrote; throws naming file, line and column on malformed input.
  static std::vector<LatencyRecord> read_csv(const std::string& path);

  /// PNG: latency over time (motion-to-swap, motion-to-display, video age) and a histogram of
  /// motion-to-display, axes labelled. Temp file + rename; throws naming the file on failure.
  void write_png(const std::string& path) const;

 private:
  LatencyStats stats_over(LatencyMetric m, std::size_t last_n) const;

  std::vector<LatencyRecord> records_;
  std::size_t next_ = 0;
  std::size_t count_ = 0;
  uint64_t total_ = 0;
  uint64_t missed_ = 0;
  mutable std::vector<int64_t> scratch_;
  mutable std::array<char, 192> hud_{};
};

}  // namespace hd::render
