#pragma once
// What hybrid-remote stamps on every RTP packet of a frame, in RFC 8285 header extensions, and the
// pure codec for it: the capture time (RFC 6051 ntp-64, written by GStreamer's rtphdrextntp64)
// and the camera's state (a small extension of this project).

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "drivers/rtp/rtp_packet.h"

namespace hd::drivers {

/// One-byte-header element ids hybrid-remote uses (the extmap it would announce in SDP).
inline constexpr uint8_t kNtp64ExtensionId = 1;
inline constexpr uint8_t kCameraStateExtensionId = 2;
inline constexpr std::string_view kNtp64ExtensionUri = "urn:ietf:params:rtp-hdrext:ntp-64";
inline constexpr std::string_view kCameraStateExtensionUri =
    "urn:hybrid-display:rtp-hdrext:camera-state";

/// Seconds from the NTP epoch (1900) to the Unix epoch (1970).
inline constexpr int64_t kNtpUnixOffsetS = 2'208'988'800LL;

/// The camera-state element's 6 bytes: version (1), camera index, calibration revision (big
/// endian u32). The revision changes whenever the sender's p_c or P_c of that camera changes.
struct CameraStateStamp {
  uint8_t camera_index = 0;
  uint32_t calibration_revision = 0;
};
inline constexpr std::size_t kCameraStateSize = 6;
inline constexpr uint8_t kCameraStateVersion = 1;

/// Why a packet's stamp was not taken (each is counted; the frame then counts as unstamped).
enum class StampError : uint8_t {
  kNone,
  kNoNtp,
  kBadNtpSize,
  kZeroNtp,
  kBadStateSize,
  kBadStateVersion,
  kCount
};
std::string_view to_string(StampError e);

/// The stamp of one packet.
struct RtpFrameStamp {
  std::optional<int64_t> capture_unix_ns;  ///< the sender's capture time, Unix epoch, ns
  std::optional<CameraStateStamp> camera;
};

/// Reads both elements of a parsed packet. A missing camera-state element is no error (a plain
/// sender); a missing ntp-64 element is kNoNtp; malformed values are refused by name.
StampError read_frame_stamp(const RtpPacketView& packet, RtpFrameStamp& out);

/// ntp-64 (32.32 fixed point seconds since 1900) <-> Unix ns; nullopt before 1970. NTP era 0 only
/// (to 2036-02-07, when the 32-bit seconds wrap).
std::optional<int64_t> ntp64_to_unix_ns(uint64_t ntp);
uint64_t unix_ns_to_ntp64(int64_t unix_ns);

/// Writes the camera-state element's 6 bytes.
void write_camera_state(const CameraStateStamp& s, std::span<uint8_t, kCameraStateSize> out);

}  // namespace hd::drivers
