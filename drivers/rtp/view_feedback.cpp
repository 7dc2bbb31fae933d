#include "drivers/rtp/view_feedback.h"

#include <cstring>

namespace hd::drivers {

std::string_view to_string(ViewFeedbackError e) {
  switch (e) {
    case ViewFeedbackError::kNone:
      return "none";
    case ViewFeedbackError::kNotViewFeedback:
      return "not view feedback";
    case ViewFeedbackError::kBadLength:
      return "bad length";
    case ViewFeedbackError::kBadVersion:
      return "bad version or flags";
    case ViewFeedbackError::kCount:
      break;
  }
  return "?";
}

void write_view_feedback(const ViewFeedback& f, std::span<uint8_t, kViewFeedbackSize> out) {
  out[0] = 0x80;  // V=2, P=0, subtype 0
  out[1] = kRtcpAppPacketType;
  out[2] = 0;
  out[3] = kViewFeedbackSize / 4 - 1;
  for (int i = 0; i < 4; ++i) out[4 + i] = uint8_t(f.ssrc >> (24 - 8 * i));
  std::memcpy(&out[8], kViewFeedbackName.data(), 4);
  out[12] = kViewFeedbackVersion;
  out[13] = f.needed ? 1 : 0;
  out[14] = uint8_t(f.sequence >> 8);
  out[15] = uint8_t(f.sequence);
}

ViewFeedbackError parse_view_feedback(std::span<const uint8_t> d, ViewFeedback& out) {
  if (d.size() < 12 || (d[0] >> 6) != 2 || d[1] != kRtcpAppPacketType ||
      std::memcmp(&d[8], kViewFeedbackName.data(), 4) != 0)
    return ViewFeedbackError::kNotViewFeedback;
  const std::size_t length_bytes = (std::size_t(d[2]) << 8 | d[3]) * 4 + 4;
  if (d.size() != kViewFeedbackSize || length_bytes != kViewFeedbackSize)
    return ViewFeedbackError::kBadLength;
  if ((d[0] & 0x3F) != 0 || d[12] != kViewFeedbackVersion || (d[13] & 0xFE) != 0)
    return ViewFeedbackError::kBadVersion;
  out.ssrc = uint32_t(d[4]) << 24 | uint32_t(d[5]) << 16 | uint32_t(d[6]) << 8 | d[7];
  out.needed = (d[13] & 1) != 0;
  out.sequence = uint16_t(d[14] << 8 | d[15]);
  return ViewFeedbackError::kNone;
}

}  // namespace hd::drivers
