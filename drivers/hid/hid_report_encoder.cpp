#include "drivers/hid/hid_report_encoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hd::drivers {
namespace {

int16_t to_count(double value, double lsb) {
  const double c = std::round(value / lsb);
  if (!std::isfinite(c)) return 0;
  return static_cast<int16_t>(std::clamp(c, -32767.0, 32767.0));
}

void write_i16(std::span<uint8_t> out, int at, int16_t v) {
  const auto u = static_cast<uint16_t>(v);
  out[static_cast<std::size_t>(at)] = static_cast<uint8_t>(u & 0xFF);
  out[static_cast<std::size_t>(at) + 1] = static_cast<uint8_t>(u >> 8);
}

}  // namespace

std::size_t encode_hid_report(const HidReportFormat& f, const HidSample& s,
                              std::span<uint8_t> out) {
  if (f.input_length_bytes <= 0 || out.size() < static_cast<std::size_t>(f.input_length_bytes))
    return 0;
  std::fill(out.begin(), out.begin() + f.input_length_bytes, uint8_t{0});
  if (f.report_id >= 0) out[0] = static_cast<uint8_t>(f.report_id);

  const Eigen::Matrix3d& A = f.head_axes_in_device;
  const Eigen::Quaterniond q_device_head(A);
  Eigen::Quaterniond q = (s.q_tracker_head.normalized() * q_device_head.conjugate()).normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // angle in [0, pi]
  const int o = f.orientation_field.offset_bytes;
  const double lsb = f.orientation_field.lsb;
  if (f.orientation == OrientationEncoding::kRotationVector) {
    const Eigen::AngleAxisd aa(q);
    const Eigen::Vector3d v = aa.axis() * aa.angle();
    for (int i = 0; i < 3; ++i) write_i16(out, o + 2 * i, to_count(v[i], lsb));
  } else {
    write_i16(out, o + 0, to_count(q.x(), lsb));
    write_i16(out, o + 2, to_count(q.y(), lsb));
    write_i16(out, o + 4, to_count(q.z(), lsb));
    write_i16(out, o + 6, to_count(q.w(), lsb));
  }
  if (f.angular_velocity_field.present()) {
    const Eigen::Vector3d w = A * s.angular_velocity_rad_s;
    for (int i = 0; i < 3; ++i)
      write_i16(out, f.angular_velocity_field.offset_bytes + 2 * i,
                to_count(w[i], f.angular_velocity_field.lsb));
  }
  if (f.discontinuity_offset_bytes >= 0)
    out[static_cast<std::size_t>(f.discontinuity_offset_bytes)] = s.discontinuity;
  if (f.sequence_offset_bytes >= 0)
    out[static_cast<std::size_t>(f.sequence_offset_bytes)] = s.sequence;
  if (f.timestamp_offset_bytes >= 0) {
    uint64_t t = s.device_timestamp;
    for (int i = 0; i < f.timestamp_bytes; ++i, t >>= 8)
      out[static_cast<std::size_t>(f.timestamp_offset_bytes + i)] = static_cast<uint8_t>(t & 0xFF);
  }
  return static_cast<std::size_t>(f.input_length_bytes);
}

std::size_t encode_control_feature(const HidReportFormat& f, bool enable, int interval_ms,
                                   std::span<uint8_t> out) {
  if (f.control_feature_id < 0 || out.size() < 2) return 0;
  out[0] = static_cast<uint8_t>(f.control_feature_id);
  uint8_t b = 0;
  if (enable) {
    const int max_ms = (1 << f.control_interval_bits) - 1;
    const int ms = std::clamp(interval_ms, f.control_interval_min_ms, max_ms);
    b = static_cast<uint8_t>(f.control_reporting_all_events_bit | f.control_power_full_bit |
                             (ms << f.control_interval_shift));
  }
  out[1] = b;
  return 2;
}

}  // namespace hd::drivers
