#include "drivers/rtp/rtp_calibration.h"

#include <bit>
#include <cmath>

#include "core/opencv_pixels.h"

namespace hd::drivers {
namespace {

void put16(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v >> 8);
  p[1] = uint8_t(v);
}
void put32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (24 - 8 * i));
}
void put_f64(uint8_t* p, double d) {
  const uint64_t v = std::bit_cast<uint64_t>(d);
  for (int i = 0; i < 8; ++i) p[i] = uint8_t(v >> (56 - 8 * i));
}
uint32_t get16(const uint8_t* p) {
  return (uint32_t{p[0]} << 8) | p[1];
}
uint32_t get32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}
double get_f64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return std::bit_cast<double>(v);
}
bool known_count(int n) {
  return n == 0 || n == 4 || n == 5 || n == 8;
}

}  // namespace

std::string_view to_string(CalibrationError e) {
  switch (e) {
    case CalibrationError::kNone:
      return "ok";
    case CalibrationError::kBadSize:
      return "calibration element of the wrong length";
    case CalibrationError::kBadVersion:
      return "calibration element of an unknown version";
    case CalibrationError::kBadDistortionCount:
      return "distortion count not 0, 4, 5 or 8";
    case CalibrationError::kNotFinite:
      return "a calibration value is not finite";
    case CalibrationError::kBadFocalLength:
      return "fx or fy not positive";
    case CalibrationError::kBadImageSize:
      return "image width or height 0";
    case CalibrationError::kNotRotation:
      return "camera_pose_R not a rotation";
    case CalibrationError::kInconsistentState:
      return "calibration camera index or revision differ from the camera-state element";
    case CalibrationError::kCount:
      break;
  }
  return "unknown";
}

std::size_t write_calibration(const StreamCalibration& c,
                              std::span<uint8_t, kCalibrationMaxSize> out) {
  const int n = c.p_c.distortion_count;
  if (!c.p_c.valid() || !known_count(n) || c.p_c.width > 0xFFFF || c.p_c.height > 0xFFFF ||
      !c.T_world_cam.valid() || !c.T_world_cam.t.allFinite())
    return 0;
  const core::OpenCvIntrinsics k = core::to_opencv(c.p_c);
  uint8_t* p = out.data();
  p[0] = kCalibrationVersion;
  p[1] = c.camera_index;
  put32(p + 2, c.revision);
  put16(p + 6, uint32_t(k.width));
  put16(p + 8, uint32_t(k.height));
  p[10] = uint8_t(n);
  p[11] = 0;
  std::size_t at = 12;
  for (const double v : {k.fx, k.fy, k.cx, k.cy}) put_f64(p + at, v), at += 8;
  for (int i = 0; i < n; ++i) put_f64(p + at, k.distortion[std::size_t(i)]), at += 8;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) put_f64(p + at, c.T_world_cam.R(r, col)), at += 8;
  for (int i = 0; i < 3; ++i) put_f64(p + at, c.T_world_cam.t[i]), at += 8;
  return at;
}

CalibrationError read_calibration(std::span<const uint8_t> e, StreamCalibration& out) {
  out = {};
  if (e.size() < kCalibrationFixedSize) return CalibrationError::kBadSize;
  const uint8_t* p = e.data();
  if (p[0] != kCalibrationVersion) return CalibrationError::kBadVersion;
  const int n = p[10];
  if (!known_count(n)) return CalibrationError::kBadDistortionCount;
  if (e.size() != calibration_element_size(n)) return CalibrationError::kBadSize;
  out.camera_index = p[1];
  out.revision = get32(p + 2);
  core::OpenCvIntrinsics k;
  k.width = int(get16(p + 6));
  k.height = int(get16(p + 8));
  k.distortion_count = n;
  std::size_t at = 12;
  bool finite = true;
  auto next = [&] {
    const double v = get_f64(p + at);
    at += 8;
    finite = finite && std::isfinite(v);
    return v;
  };
  k.fx = next();
  k.fy = next();
  k.cx = next();
  k.cy = next();
  for (int i = 0; i < n; ++i) k.distortion[std::size_t(i)] = next();
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col) out.T_world_cam.R(r, col) = next();
  for (int i = 0; i < 3; ++i) out.T_world_cam.t[i] = next();
  if (!finite) return CalibrationError::kNotFinite;
  if (!(k.fx > 0.0) || !(k.fy > 0.0)) return CalibrationError::kBadFocalLength;
  if (k.width == 0 || k.height == 0) return CalibrationError::kBadImageSize;
  if (!out.T_world_cam.valid()) return CalibrationError::kNotRotation;
  out.p_c = core::from_opencv(k);  // n is one of 0/4/5/8: cannot throw
  return CalibrationError::kNone;
}

CalibrationError read_packet_calibration(const RtpPacketView& packet,
                                         const std::optional<CameraStateStamp>& state,
                                         std::optional<StreamCalibration>& out) {
  out.reset();
  std::span<const uint8_t> d;
  if (!find_rtp_extension(packet, kCalibrationExtensionId, d)) return CalibrationError::kNone;
  StreamCalibration c;
  const CalibrationError e = read_calibration(d, c);
  if (e != CalibrationError::kNone) return e;
  if (state && (state->camera_index != c.camera_index || state->calibration_revision != c.revision))
    return CalibrationError::kInconsistentState;
  out = c;
  return CalibrationError::kNone;
}

}  // namespace hd::drivers
