#pragma once
// Pure HID input report parser: bytes + HidReportFormat -> a validated sample or a reason.
// No I/O, no allocation; safe on any input (fuzzed).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <string_view>

#include "drivers/hid/hid_report_format.h"

namespace hd::drivers {

enum class HidRejectReason : uint8_t {
  kWrongLength,
  kWrongReportId,
  kForbiddenValue,  ///< -32768 in a field of a format that forbids it
  kNonFinite,       ///< a scaled value came out NaN or infinite
  kOutOfRange,      ///< rotation vector longer than the format allows
  kUnnormalisable,  ///< quaternion too far from unit length to be a rotation
  kCount
};

std::string_view to_string(HidRejectReason r);

struct HidSample {
  Eigen::Quaterniond q_tracker_head = Eigen::Quaterniond::Identity();  ///< station head axes
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();    ///< station head axes
  bool has_angular_velocity = false;
  bool has_discontinuity = false;
  uint8_t discontinuity = 0;
  bool has_sequence = false;
  uint8_t sequence = 0;
  bool has_timestamp = false;
  uint64_t device_timestamp = 0;  ///< raw counter, see HidReportFormat::timestamp_tick_ns
};

struct HidParseResult {
  bool ok = false;
  HidRejectReason reason = HidRejectReason::kWrongLength;
  HidSample sample;
};

HidParseResult parse_hid_report(const HidReportFormat& format, std::span<const uint8_t> report);

/// Per-reason counters, written by the read thread, read from anywhere.
class HidRejectCounters {
 public:
  void count(HidRejectReason r) {
    counts_[static_cast<std::size_t>(r)].fetch_add(1, std::memory_order_relaxed);
  }
  uint64_t get(HidRejectReason r) const {
    return counts_[static_cast<std::size_t>(r)].load(std::memory_order_relaxed);
  }
  uint64_t total() const {
    uint64_t t = 0;
    for (const auto& c : counts_) t += c.load(std::memory_order_relaxed);
    return t;
  }

 private:
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(HidRejectReason::kCount)> counts_{};
};

}  // namespace hd::drivers
