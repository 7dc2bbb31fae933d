#pragma once
// A head tracker's HID report layout as DATA: which bytes hold which field and how to scale them.
// One parser reads every format; supporting a new tracker means writing a new HidReportFormat,
// not new code (the split Monado uses between transport and packet parsing).

#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace hd::drivers {

/// A little-endian int16 field array inside a report. value = raw * lsb.
struct Int16Vector {
  int offset_bytes = -1;  ///< first byte (report id included, if the format has one); -1: absent
  double lsb = 1.0;       ///< physical units per count (e.g. 2^-14 for 14 fractional bits)
  bool present() const { return offset_bytes >= 0; }
};

enum class OrientationEncoding : uint8_t {
  kRotationVector,  ///< int16 x3, axis * angle (Android head tracker)
  kQuaternion,      ///< int16 x4 fixed point, stored x, y, z, w (OSVR HDK)
};

struct HidReportFormat {
  std::string name;
  int report_id = -1;            ///< first byte of every input report; -1: reports carry no id
  int input_length_bytes = 0;    ///< exact length of a valid input report (id byte included)
  bool forbid_int16_min = true;  ///< -32768 marks an invalid value (Android protocol)

  OrientationEncoding orientation = OrientationEncoding::kRotationVector;
  Int16Vector orientation_field;       ///< 3 (rotation vector) or 4 (quaternion) components
  double max_rotation_angle_rad = 0;   ///< rotation vector magnitude limit (0: not checked)
  Int16Vector angular_velocity_field;  ///< 3 components in rad/s, device head frame

  int discontinuity_offset_bytes = -1;  ///< uint8 counter bumped on reference-frame jumps
  int sequence_offset_bytes = -1;       ///< uint8 report sequence number

  /// Optional device timestamp (little endian, `timestamp_bytes` wide, `timestamp_tick_ns` per
  /// count). Neither built-in format has one: their samples are stamped on arrival.
  int timestamp_offset_bytes = -1;
  int timestamp_bytes = 0;
  double timestamp_tick_ns = 1000.0;

  /// Columns: the station's head axes (x right, y down, z forward; DESIGN.md) expressed in the
  /// device's head frame. R_tracker_head = R_tracker_devicehead * head_axes_in_device.
  Eigen::Matrix3d head_axes_in_device = Eigen::Matrix3d::Identity();

  // Start-up handshake (feature reports). Empty description: no check.
  int description_feature_id = -1;
  std::string description;  ///< e.g. "#AndroidHeadTracker#1.0", no terminator
  int control_feature_id = -1;
  /// The control byte written to start streaming: reporting state, power state, interval.
  uint8_t control_reporting_all_events_bit = 0x01;
  uint8_t control_power_full_bit = 0x02;
  int control_interval_shift = 2;  ///< interval (ms) occupies the bits from here up
  int control_interval_bits = 6;
  int control_interval_min_ms = 10;
};

/// Android head tracker HID protocol 1.0 (usage page Sensors 0x20, usage Other: Custom 0xE1),
/// report ids as in the protocol's example descriptor: 1 = description + unique id (feature),
/// 2 = reporting state / power state / interval (feature), 3 = input.
HidReportFormat android_head_tracker_v1();

/// OSVR HDK tracker (Razer 1532:0b00): 32-byte report, version byte, sequence byte, quaternion
/// with 14 fractional bits, angular velocity with 9.
HidReportFormat osvr_hdk();

/// HID usage of the Android head tracker's application collection, for enumeration.
constexpr uint16_t kSensorsUsagePage = 0x20;
constexpr uint16_t kCustomSensorUsage = 0xE1;

}  // namespace hd::drivers
