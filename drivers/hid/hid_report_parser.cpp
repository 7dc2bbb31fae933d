#include "drivers/hid/hid_report_parser.h"

#include <cmath>

namespace hd::drivers {
namespace {

int16_t read_i16(std::span<const uint8_t> r, std::size_t at) {
  return static_cast<int16_t>(static_cast<uint16_t>(r[at]) |
                              static_cast<uint16_t>(static_cast<uint16_t>(r[at + 1]) << 8));
}

// Reads `n` int16 components; false when a field does not fit the format's length.
bool read_components(const HidReportFormat& f, std::span<const uint8_t> r, const Int16Vector& v,
                     int n, int16_t* out) {
  if (v.offset_bytes < 0 || v.offset_bytes + 2 * n > f.input_length_bytes) return false;
  for (int i = 0; i < n; ++i)
    out[i] = read_i16(r, static_cast<std::size_t>(v.offset_bytes + 2 * i));
  return true;
}

bool has_forbidden(const int16_t* v, int n) {
  for (int i = 0; i < n; ++i)
    if (v[i] == INT16_MIN) return true;
  return false;
}

HidParseResult reject(HidRejectReason r) {
  return {false, r, {}};
}

}  // namespace

std::string_view to_string(HidRejectReason r) {
  switch (r) {
    case HidRejectReason::kWrongLength:
      return "wrong length";
    case HidRejectReason::kWrongReportId:
      return "wrong report id";
    case HidRejectReason::kForbiddenValue:
      return "forbidden value -32768";
    case HidRejectReason::kNonFinite:
      return "non-finite value";
    case HidRejectReason::kOutOfRange:
      return "rotation out of range";
    case HidRejectReason::kUnnormalisable:
      return "unnormalisable quaternion";
    case HidRejectReason::kCount:
      break;
  }
  return "unknown";
}

HidParseResult parse_hid_report(const HidReportFormat& f, std::span<const uint8_t> report) {
  if (f.input_length_bytes <= 0 || report.size() != static_cast<std::size_t>(f.input_length_bytes))
    return reject(HidRejectReason::kWrongLength);
  if (f.report_id >= 0 && report[0] != static_cast<uint8_t>(f.report_id))
    return reject(HidRejectReason::kWrongReportId);

  HidParseResult out;
  HidSample& s = out.sample;
  const Eigen::Matrix3d& A = f.head_axes_in_device;

  int16_t o[4] = {0, 0, 0, 0};
  const int n_orientation = f.orientation == OrientationEncoding::kQuaternion ? 4 : 3;
  if (!read_components(f, report, f.orientation_field, n_orientation, o))
    return reject(HidRejectReason::kWrongLength);
  if (f.forbid_int16_min && has_forbidden(o, n_orientation))
    return reject(HidRejectReason::kForbiddenValue);

  Eigen::Quaterniond q_tracker_device;
  if (f.orientation == OrientationEncoding::kRotationVector) {
    const Eigen::Vector3d v(o[0] * f.orientation_field.lsb, o[1] * f.orientation_field.lsb,
                            o[2] * f.orientation_field.lsb);
    if (!v.allFinite()) return reject(HidRejectReason::kNonFinite);
    const double angle = v.norm();
    // One count of slack: each component is rounded to the nearest count.
    if (f.max_rotation_angle_rad > 0 &&
        angle > f.max_rotation_angle_rad + 2.0 * f.orientation_field.lsb)
      return reject(HidRejectReason::kOutOfRange);
    q_tracker_device = angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, v / angle))
                                 : Eigen::Quaterniond::Identity();
  } else {
    const double lsb = f.orientation_field.lsb;
    Eigen::Quaterniond q(o[3] * lsb, o[0] * lsb, o[1] * lsb, o[2] * lsb);
    if (!q.coeffs().allFinite()) return reject(HidRejectReason::kNonFinite);
    const double norm = q.norm();
    // A fixed-point unit quaternion is within a few counts of length 1; far from it the data is
    // not a rotation at all (noise, a zeroed report, a different layout).
    if (!(norm > 0.9 && norm < 1.1)) return reject(HidRejectReason::kUnnormalisable);
    q_tracker_device = q.normalized();
  }
  if (!q_tracker_device.coeffs().allFinite()) return reject(HidRejectReason::kNonFinite);
  // R_tracker_head = R_tracker_device * A, with A's columns the station head axes in the device.
  const Eigen::Quaterniond q_device_head(A);
  s.q_tracker_head = (q_tracker_device * q_device_head).normalized();

  if (f.angular_velocity_field.present()) {
    int16_t w[3];
    if (!read_components(f, report, f.angular_velocity_field, 3, w))
      return reject(HidRejectReason::kWrongLength);
    if (f.forbid_int16_min && has_forbidden(w, 3)) return reject(HidRejectReason::kForbiddenValue);
    const Eigen::Vector3d w_device(w[0] * f.angular_velocity_field.lsb,
                                   w[1] * f.angular_velocity_field.lsb,
                                   w[2] * f.angular_velocity_field.lsb);
    if (!w_device.allFinite()) return reject(HidRejectReason::kNonFinite);
    s.angular_velocity_rad_s = A.transpose() * w_device;
    s.has_angular_velocity = true;
  }
  if (f.discontinuity_offset_bytes >= 0) {
    if (f.discontinuity_offset_bytes >= f.input_length_bytes)
      return reject(HidRejectReason::kWrongLength);
    s.discontinuity = report[static_cast<std::size_t>(f.discontinuity_offset_bytes)];
    s.has_discontinuity = true;
  }
  if (f.sequence_offset_bytes >= 0) {
    if (f.sequence_offset_bytes >= f.input_length_bytes)
      return reject(HidRejectReason::kWrongLength);
    s.sequence = report[static_cast<std::size_t>(f.sequence_offset_bytes)];
    s.has_sequence = true;
  }
  if (f.timestamp_offset_bytes >= 0) {
    if (f.timestamp_bytes < 1 || f.timestamp_bytes > 8 ||
        f.timestamp_offset_bytes + f.timestamp_bytes > f.input_length_bytes)
      return reject(HidRejectReason::kWrongLength);
    uint64_t t = 0;
    for (int i = f.timestamp_bytes - 1; i >= 0; --i)
      t = (t << 8) | report[static_cast<std::size_t>(f.timestamp_offset_bytes + i)];
    s.device_timestamp = t;
    s.has_timestamp = true;
  }
  out.ok = true;
  return out;
}

}  // namespace hd::drivers
