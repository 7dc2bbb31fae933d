#include "drivers/mock/mock_head_tracker_transport.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/hid/hid_report_encoder.h"

namespace hd::drivers {

MockHeadTrackerTransport::MockHeadTrackerTransport(MockHeadTrackerConfig config)
    : config_(std::move(config)), open_ns_(monotonic_now_ns()) {}

int MockHeadTrackerTransport::read_report(std::span<uint8_t> buffer, int timeout_ms) {
  if (!config_.control->plugged_in.load()) return -1;
  const int64_t now = monotonic_now_ns();
  const int64_t deadline = now + static_cast<int64_t>(std::max(timeout_ms, 0)) * 1'000'000;
  if (interval_ns_ == 0 || next_report_ns_ > deadline) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(deadline - now));
    return config_.control->plugged_in.load() ? 0 : -1;
  }
  if (next_report_ns_ > now)
    std::this_thread::sleep_for(std::chrono::nanoseconds(next_report_ns_ - now));
  HidSample s;
  if (config_.motion) {
    const TrajectorySample m =
        config_.motion(static_cast<double>(next_report_ns_ - open_ns_) * 1e-9);
    s.q_tracker_head = m.q;
    // Angular velocity by central difference, as a real gyro would report it.
    constexpr double kH = 1e-4;
    const double t = static_cast<double>(next_report_ns_ - open_ns_) * 1e-9;
    const Eigen::AngleAxisd d(config_.motion(t - kH).q.conjugate() * config_.motion(t + kH).q);
    s.angular_velocity_rad_s = d.axis() * (d.angle() / (2 * kH));
  }
  s.discontinuity = config_.control->discontinuity.load();
  next_report_ns_ += interval_ns_;
  const std::size_t n = encode_hid_report(config_.format, s, buffer);
  if (n == 0) return -1;
  config_.control->reports_sent.fetch_add(1);
  return static_cast<int>(n);
}

int MockHeadTrackerTransport::get_feature_report(std::span<uint8_t> buffer) {
  const HidReportFormat& f = config_.format;
  if (!config_.control->plugged_in.load() || buffer.empty()) return -1;
  if (buffer[0] != f.description_feature_id) return -1;
  // Description (no terminator) followed by a 16-byte all-zero persistent unique id.
  const std::size_t n = 1 + f.description.size() + 16;
  if (buffer.size() < n) return -1;
  std::memcpy(buffer.data() + 1, f.description.data(), f.description.size());
  std::fill(buffer.begin() + 1 + static_cast<std::ptrdiff_t>(f.description.size()),
            buffer.begin() + static_cast<std::ptrdiff_t>(n), uint8_t{0});
  return static_cast<int>(n);
}

int MockHeadTrackerTransport::send_feature_report(std::span<const uint8_t> report) {
  const HidReportFormat& f = config_.format;
  if (!config_.control->plugged_in.load()) return -1;
  if (report.size() < 2 || report[0] != f.control_feature_id) return -1;
  const uint8_t b = report[1];
  const bool on =
      (b & f.control_reporting_all_events_bit) != 0 && (b & f.control_power_full_bit) != 0;
  const int interval_ms = (b >> f.control_interval_shift) & ((1 << f.control_interval_bits) - 1);
  interval_ns_ =
      on ? static_cast<int64_t>(std::max(interval_ms, f.control_interval_min_ms)) * 1'000'000 : 0;
  next_report_ns_ = monotonic_now_ns();
  return static_cast<int>(report.size());
}

HidTransportOpener mock_head_tracker_opener(MockHeadTrackerConfig config) {
  return [config](std::string& why) -> std::unique_ptr<HidTransport> {
    if (!config.control->plugged_in.load()) {
      why = "mock head tracker unplugged";
      return nullptr;
    }
    return std::make_unique<MockHeadTrackerTransport>(config);
  };
}

}  // namespace hd::drivers
