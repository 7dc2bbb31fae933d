#include "drivers/hid/hid_report_format.h"

#include <cmath>
#include <numbers>

namespace hd::drivers {

HidReportFormat android_head_tracker_v1() {
  HidReportFormat f;
  f.name = "android-head-tracker-1.0";
  f.report_id = 3;
  // id, rotation vector int16 x3, angular velocity int16 x3, discontinuity count uint8.
  f.input_length_bytes = 1 + 6 + 6 + 1;
  f.forbid_int16_min = true;
  f.orientation = OrientationEncoding::kRotationVector;
  f.orientation_field = {.offset_bytes = 1, .lsb = std::numbers::pi / 32767.0};
  f.max_rotation_angle_rad = std::numbers::pi;
  f.angular_velocity_field = {.offset_bytes = 7, .lsb = 32.0 / 32767.0};
  f.discontinuity_offset_bytes = 13;
  // Android head frame: X towards the right ear, Y towards the nose, Z to the top of the head.
  // Station head: x right, y down, z forward.
  f.head_axes_in_device << 1, 0, 0,  //
      0, 0, 1,                       //
      0, -1, 0;
  f.description_feature_id = 1;
  f.description = "#AndroidHeadTracker#1.0";
  f.control_feature_id = 2;
  return f;
}

HidReportFormat osvr_hdk() {
  HidReportFormat f;
  f.name = "osvr-hdk";
  f.report_id = -1;  // hidraw delivers the 32-byte report with no id; byte 0 is a version
  f.input_length_bytes = 32;
  f.forbid_int16_min = false;  // plain fixed point: -32768 is -2.0, caught by the norm check
  f.orientation = OrientationEncoding::kQuaternion;
  f.orientation_field = {.offset_bytes = 2, .lsb = std::ldexp(1.0, -14)};
  f.angular_velocity_field = {.offset_bytes = 10, .lsb = std::ldexp(1.0, -9)};
  f.sequence_offset_bytes = 1;
  // OSVR frame: x right, y up, z backwards (out of the face).
  f.head_axes_in_device << 1, 0, 0,  //
      0, -1, 0,                      //
      0, 0, -1;
  return f;
}

}  // namespace hd::drivers
