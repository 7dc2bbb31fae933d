#include "drivers/rtp/rtp_frame_stamp.h"

namespace hd::drivers {

std::string_view to_string(StampError e) {
  switch (e) {
    case StampError::kNone:
      return "ok";
    case StampError::kNoNtp:
      return "no ntp-64 element";
    case StampError::kBadNtpSize:
      return "ntp-64 element not 8 bytes";
    case StampError::kZeroNtp:
      return "ntp-64 time before 1970";
    case StampError::kBadStateSize:
      return "camera-state element not 6 bytes";
    case StampError::kBadStateVersion:
      return "camera-state element of an unknown version";
    case StampError::kBadStagesSize:
      return "sender-stages element not 14 bytes";
    case StampError::kBadStagesVersion:
      return "sender-stages element of an unknown version";
    case StampError::kCount:
      break;
  }
  return "unknown";
}

std::optional<int64_t> ntp64_to_unix_ns(uint64_t ntp) {
  const uint64_t seconds = ntp >> 32;
  if (seconds < uint64_t(kNtpUnixOffsetS)) return std::nullopt;
  const uint64_t fraction = ntp & 0xFFFFFFFFu;
  // Rounded to the nearest ns: 2^32 fractions per second.
  const uint64_t frac_ns = (fraction * 1'000'000'000ull + (1ull << 31)) >> 32;
  return int64_t(seconds - uint64_t(kNtpUnixOffsetS)) * 1'000'000'000LL + int64_t(frac_ns);
}

uint64_t unix_ns_to_ntp64(int64_t unix_ns) {
  const uint64_t s = uint64_t(unix_ns / 1'000'000'000LL) + uint64_t(kNtpUnixOffsetS);
  const uint64_t ns = uint64_t(unix_ns % 1'000'000'000LL);
  return (s << 32) | (((ns << 32) + 500'000'000ull) / 1'000'000'000ull);
}

namespace {

uint32_t be32(std::span<const uint8_t> d) {
  return (uint32_t{d[0]} << 24) | (uint32_t{d[1]} << 16) | (uint32_t{d[2]} << 8) | d[3];
}

void put_be32(uint32_t v, uint8_t* out) {
  out[0] = uint8_t(v >> 24);
  out[1] = uint8_t(v >> 16);
  out[2] = uint8_t(v >> 8);
  out[3] = uint8_t(v);
}

}  // namespace

StampError read_frame_stamp(const RtpPacketView& packet, RtpFrameStamp& out) {
  out = {};
  std::span<const uint8_t> d;
  if (find_rtp_extension(packet, kCameraStateExtensionId, d)) {
    if (d.size() != kCameraStateSize) return StampError::kBadStateSize;
    if (d[0] != kCameraStateVersion) return StampError::kBadStateVersion;
    CameraStateStamp s;
    s.camera_index = d[1];
    s.calibration_revision = be32(d.subspan(2));
    out.camera = s;
  }
  if (find_rtp_extension(packet, kSenderStagesExtensionId, d)) {
    if (d.size() != kSenderStagesSize) return StampError::kBadStagesSize;
    if (d[0] != kSenderStagesVersion) return StampError::kBadStagesVersion;
    SenderStagesStamp s;
    s.round_trip_count = d[1];
    s.encoded_us = be32(d.subspan(2));
    s.sent_us = be32(d.subspan(6));
    s.round_trip_us = be32(d.subspan(10));
    out.stages = s;
  }
  if (!find_rtp_extension(packet, kNtp64ExtensionId, d)) return StampError::kNoNtp;
  if (d.size() != 8) return StampError::kBadNtpSize;
  uint64_t ntp = 0;
  for (const uint8_t b : d) ntp = (ntp << 8) | b;
  out.capture_unix_ns = ntp64_to_unix_ns(ntp);
  if (!out.capture_unix_ns) return StampError::kZeroNtp;
  return StampError::kNone;
}

void write_camera_state(const CameraStateStamp& s, std::span<uint8_t, kCameraStateSize> out) {
  out[0] = kCameraStateVersion;
  out[1] = s.camera_index;
  put_be32(s.calibration_revision, &out[2]);
}

void write_sender_stages(const SenderStagesStamp& s, std::span<uint8_t, kSenderStagesSize> out) {
  out[0] = kSenderStagesVersion;
  out[1] = s.round_trip_count;
  put_be32(s.encoded_us, &out[2]);
  put_be32(s.sent_us, &out[6]);
  put_be32(s.round_trip_us, &out[10]);
}

}  // namespace hd::drivers
