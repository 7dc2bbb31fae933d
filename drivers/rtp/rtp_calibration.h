#pragma once
// The calibration element hybrid-remote puts on the last packet of every frame (RFC 8285
// two-byte header element, id 3, urn:hybrid-display:rtp-hdrext:calibration): the camera's p_c
// with its distortion and its pose P_c, and the pure codec for it (docs/network.md).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/rtp_packet.h"

namespace hd::drivers {

inline constexpr uint8_t kCalibrationExtensionId = 3;
inline constexpr std::string_view kCalibrationExtensionUri =
    "urn:hybrid-display:rtp-hdrext:calibration";
inline constexpr uint8_t kCalibrationVersion = 1;
/// Bytes without distortion coefficients; each coefficient adds 8 (at most 8 of them: 204).
inline constexpr std::size_t kCalibrationFixedSize = 140;
inline constexpr std::size_t kCalibrationMaxSize = kCalibrationFixedSize + 8 * 8;

/// One camera's calibration as the stream carries it. p_c is in core's convention here (pixel
/// centres at +0.5); on the wire the principal point is OpenCV's, as in the calibration file.
struct StreamCalibration {
  uint8_t camera_index = 0;
  uint32_t revision = 0;
  core::Pinhole p_c;
  core::Pose T_world_cam;  ///< camera-to-world, t the camera centre (metres)
};

/// Why a calibration element was refused (counted by reason; the element is then ignored).
enum class CalibrationError : uint8_t {
  kNone,
  kBadSize,             ///< length not 140 + 8 n for its distortion count n
  kBadVersion,          ///< not version 1
  kBadDistortionCount,  ///< n not 0, 4, 5 or 8
  kNotFinite,           ///< a NaN or infinity anywhere
  kBadFocalLength,      ///< fx or fy <= 0
  kBadImageSize,        ///< width or height 0
  kNotRotation,         ///< R not orthonormal with det +1 (to 1e-6)
  kInconsistentState,   ///< camera index or revision differ from the packet's camera-state
  kCount
};
std::string_view to_string(CalibrationError e);

/// Element bytes for distortion count n.
constexpr std::size_t calibration_element_size(int distortion_count) {
  return kCalibrationFixedSize + 8 * static_cast<std::size_t>(distortion_count);
}

/// Encodes `c` (doubles as IEEE 754 binary64, big endian, bit for bit); returns the bytes
/// written, 0 when `c` cannot be sent (not a valid pinhole, a size above 65535, a distortion
/// count other than 0/4/5/8, a pose that is not a rotation).
std::size_t write_calibration(const StreamCalibration& c,
                              std::span<uint8_t, kCalibrationMaxSize> out);

/// Decodes and checks one element's bytes. Never reads outside `element`.
CalibrationError read_calibration(std::span<const uint8_t> element, StreamCalibration& out);

/// The calibration element of a parsed packet, checked against the packet's camera-state (same
/// camera index and revision) when it has one. kNone with `out` empty when there is none.
CalibrationError read_packet_calibration(const RtpPacketView& packet,
                                         const std::optional<CameraStateStamp>& state,
                                         std::optional<StreamCalibration>& out);

}  // namespace hd::drivers
