#include "drivers/rtp/view_feedback.h"

#include <glib.h>

#include <cstring>
#include <string_view>

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
    case ViewFeedbackError::kNotAuthenticated:
      return "not authenticated";
    case ViewFeedbackError::kBadTag:
      return "bad authentication tag";
    case ViewFeedbackError::kCount:
      break;
  }
  return "?";
}

namespace {

std::array<uint8_t, 32> hmac_sha256(std::span<const uint8_t> key, std::span<const uint8_t> data) {
  GHmac* h = g_hmac_new(G_CHECKSUM_SHA256, key.data(), key.size());
  g_hmac_update(h, data.data(), static_cast<gssize>(data.size()));
  std::array<uint8_t, 32> digest{};
  gsize length = digest.size();
  g_hmac_get_digest(h, digest.data(), &length);
  g_hmac_unref(h);
  return digest;
}

constexpr std::size_t kTagBytes = kAuthenticatedViewFeedbackSize - kViewFeedbackSize;

void write_fields(const ViewFeedback& f, uint8_t version, std::size_t size, uint8_t* out) {
  out[0] = 0x80;  // V=2, P=0, subtype 0
  out[1] = kRtcpAppPacketType;
  out[2] = 0;
  out[3] = uint8_t(size / 4 - 1);
  for (int i = 0; i < 4; ++i) out[4 + i] = uint8_t(f.ssrc >> (24 - 8 * i));
  std::memcpy(&out[8], kViewFeedbackName.data(), 4);
  out[12] = version;
  out[13] = f.needed ? 1 : 0;
  out[14] = uint8_t(f.sequence >> 8);
  out[15] = uint8_t(f.sequence);
}

}  // namespace

ViewFeedbackKey view_feedback_key(const SrtpKey& srtp) {
  constexpr std::string_view kLabel = "hybrid-display view feedback";
  ViewFeedbackKey k;
  k.bytes = hmac_sha256(srtp.bytes,
                        std::span(reinterpret_cast<const uint8_t*>(kLabel.data()), kLabel.size()));
  return k;
}

void write_view_feedback(const ViewFeedback& f, std::span<uint8_t, kViewFeedbackSize> out) {
  write_fields(f, kViewFeedbackVersion, kViewFeedbackSize, out.data());
}

void write_view_feedback(const ViewFeedback& f, const ViewFeedbackKey& key,
                         std::span<uint8_t, kAuthenticatedViewFeedbackSize> out) {
  write_fields(f, kAuthenticatedViewFeedbackVersion, kAuthenticatedViewFeedbackSize, out.data());
  const auto tag = hmac_sha256(key.bytes, out.first(kViewFeedbackSize));
  std::memcpy(&out[kViewFeedbackSize], tag.data(), kTagBytes);
}

ViewFeedbackError parse_view_feedback(std::span<const uint8_t> d, const ViewFeedbackKey* key,
                                      ViewFeedback& out) {
  if (d.size() < 12 || (d[0] >> 6) != 2 || d[1] != kRtcpAppPacketType ||
      std::memcmp(&d[8], kViewFeedbackName.data(), 4) != 0)
    return ViewFeedbackError::kNotViewFeedback;
  const bool authenticated = d.size() > 12 && d[12] == kAuthenticatedViewFeedbackVersion;
  const std::size_t size = authenticated ? kAuthenticatedViewFeedbackSize : kViewFeedbackSize;
  const std::size_t length_bytes = (std::size_t(d[2]) << 8 | d[3]) * 4 + 4;
  if (d.size() != size || length_bytes != size) return ViewFeedbackError::kBadLength;
  if ((d[0] & 0x3F) != 0 || (d[12] != kViewFeedbackVersion && !authenticated) ||
      (d[13] & 0xFE) != 0 || (authenticated && key == nullptr))
    return ViewFeedbackError::kBadVersion;
  if (key != nullptr && !authenticated) return ViewFeedbackError::kNotAuthenticated;
  if (key != nullptr) {
    const auto tag = hmac_sha256(key->bytes, d.first(kViewFeedbackSize));
    uint8_t diff = 0;  // every byte compared: the time taken says nothing about the tag
    for (std::size_t i = 0; i < kTagBytes; ++i) diff |= uint8_t(tag[i] ^ d[kViewFeedbackSize + i]);
    if (diff != 0) return ViewFeedbackError::kBadTag;
  }
  out.ssrc = uint32_t(d[4]) << 24 | uint32_t(d[5]) << 16 | uint32_t(d[6]) << 8 | d[7];
  out.needed = (d[13] & 1) != 0;
  out.sequence = uint16_t(d[14] << 8 | d[15]);
  return ViewFeedbackError::kNone;
}

}  // namespace hd::drivers
