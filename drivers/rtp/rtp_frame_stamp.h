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
inline constexpr uint8_t kSenderStagesExtensionId = 4;
inline constexpr std::string_view kNtp64ExtensionUri = "urn:ietf:params:rtp-hdrext:ntp-64";
inline constexpr std::string_view kCameraStateExtensionUri =
    "urn:hybrid-display:rtp-hdrext:camera-state";
inline constexpr std::string_view kSenderStagesExtensionUri =
    "urn:hybrid-display:rtp-hdrext:sender-stages";

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

/// The sender-stages element's 14 bytes: version (1), round-trip count (u8, wraps; 0 = none
/// measured yet), then big endian u32s: microseconds from the frame's capture to its encoded
/// frame reaching the payloader, to this packet leaving the payloader (sent), and the newest
/// round trip to the station the sender measured from the station's receiver reports (RFC 3550
/// A.8). Durations on the sender's clock, so the station needs no offset to use them.
struct SenderStagesStamp {
  uint32_t encoded_us = 0;
  uint32_t sent_us = 0;
  uint8_t round_trip_count = 0;
  uint32_t round_trip_us = 0;
};
inline constexpr std::size_t kSenderStagesSize = 14;
inline constexpr uint8_t kSenderStagesVersion = 1;

/// Why a packet's stamp was not taken (each is counted; the frame then counts as unstamped).
enum class StampError : uint8_t {
  kNone,
  kNoNtp,
  kBadNtpSize,
  kZeroNtp,
  kBadStateSize,
  kBadStateVersion,
  kBadStagesSize,
  kBadStagesVersion,
  kCount
};
std::string_view to_string(StampError e);

/// The stamp of one packet.
struct RtpFrameStamp {
  std::optional<int64_t> capture_unix_ns;  ///< the sender's capture time, Unix epoch, ns
  std::optional<CameraStateStamp> camera;
  std::optional<SenderStagesStamp> stages;
};

/// Reads the elements of a parsed packet. A missing camera-state or sender-stages element is no
/// error (a plain sender); a missing ntp-64 element is kNoNtp; malformed values are refused by
/// name.
StampError read_frame_stamp(const RtpPacketView& packet, RtpFrameStamp& out);

/// ntp-64 (32.32 fixed point seconds since 1900) <-> Unix ns; nullopt before 1970. NTP era 0 only
/// (to 2036-02-07, when the 32-bit seconds wrap).
std::optional<int64_t> ntp64_to_unix_ns(uint64_t ntp);
uint64_t unix_ns_to_ntp64(int64_t unix_ns);

/// Writes the camera-state element's 6 bytes.
void write_camera_state(const CameraStateStamp& s, std::span<uint8_t, kCameraStateSize> out);
/// Writes the sender-stages element's 14 bytes.
void write_sender_stages(const SenderStagesStamp& s, std::span<uint8_t, kSenderStagesSize> out);

}  // namespace hd::drivers
