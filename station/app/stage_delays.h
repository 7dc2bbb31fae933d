#pragma once
// Each stage's delay, for the HUD and the summary: for a camera's frames capture -> encoded ->
// sent -> received -> decoded -> on screen, and for the model capture -> reconstructed -> in the
// model -> on screen. Each stage is kept as the time since capture (so
// the last one is the whole delay and each step is a difference), as p50 over the last second
// and over the run. Pure: times in, figures out; fed between frames (it may allocate there).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hd::station {

/// p50 over a sliding second and over the run, of one time-since-capture (ms).
class StageSeries {
 public:
  /// A sample of `ms` at `now_ns` (NaN or negative: not a sample).
  void add(double ms, int64_t now_ns);
  /// p50 of the samples of the last second before `now_ns` (NaN: none).
  double p50_last_second(int64_t now_ns) const;
  /// p50 over the run, to the histogram's 0.1 ms (NaN: none); samples over 2 s count as 2 s.
  double p50_run() const;
  uint64_t count() const { return count_; }

 private:
  static constexpr std::size_t kRecent = 512;  // a second at up to 512 frames per second
  static constexpr double kBinMs = 0.1;
  static constexpr std::size_t kBins = 20'000;  // 2 s
  std::array<double, kRecent> recent_ms_{};
  std::array<int64_t, kRecent> recent_at_ns_{};
  std::size_t next_ = 0;
  std::vector<uint32_t> histogram_;
  uint64_t count_ = 0;
};

/// The stages of one source, in order; stage 0 is capture itself (always 0 ms).
class StageDelays {
 public:
  /// A camera's: capture, encoded, sent, received, decoded (a network camera's link), on screen.
  static StageDelays video();
  /// The model's: capture, reconstructed, in the model, on screen.
  static StageDelays model();

  /// The stages' names for the summary ("encoded", ...), and their short ones for the HUD.
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& short_names() const { return short_names_; }
  StageSeries& stage(std::size_t i) { return series_.at(i); }
  const StageSeries& stage(std::size_t i) const { return series_.at(i); }

  /// "enc 8.1 > sent 8.5 > ... > shown 27.3 ms" with the last second's p50s of the time since
  /// capture (stages with no sample left out; "" when none has one).
  std::string hud_text(int64_t now_ns) const;

 private:
  StageDelays(std::vector<std::string> names, std::vector<std::string> short_names);
  std::vector<std::string> names_, short_names_;
  std::vector<StageSeries> series_;
};

}  // namespace hd::station
