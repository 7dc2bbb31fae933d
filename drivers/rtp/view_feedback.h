#pragma once
// The station's "which cameras it uses" feedback to the remote site (bandwidth follows the view,
// issue 12 item 5): one RTCP APP packet (RFC 3550 section 6.7) per camera stream, pure writer and
// parser.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "drivers/rtp/srtp_key.h"

namespace hd::drivers {

/// Wire format, 16 bytes, sent by the station to the address the camera's sender reports come
/// from (hybrid-remote's RTCP socket), on its own (not inside a compound RTCP packet):
///
///   V=2 P=0 subtype=0 | PT=204 (APP) | length=3        (RFC 3550 section 6.7)
///   SSRC of the station's session (0: not known)
///   name "HDBW"
///   version=1 | flags (bit 0: needed) | sequence (u16 big endian, +1 per message)
///
/// "needed": the station uses the camera, or may use it soon; not needed: send it at a low rate
/// until it is needed again.
///
/// With the stream's SRTP key configured (both ends have it), the message is version 2, 32 bytes
/// (length=7): the 16 bytes above followed by a 16-byte tag, HMAC-SHA256 over those 16 bytes
/// truncated to its first half (RFC 2104 section 5), keyed not with the SRTP master key itself
/// but with HMAC-SHA256(master key + salt, "hybrid-display view feedback"), so that one key is
/// never used by two algorithms. The sequence number keeps a replay from reversing a newer
/// message; a replay after the station fell silent is taken (the sender then sends at full rate
/// within view_feedback_timeout_s of the station's return anyway).
inline constexpr std::size_t kViewFeedbackSize = 16;
inline constexpr uint8_t kViewFeedbackVersion = 1;
inline constexpr std::size_t kAuthenticatedViewFeedbackSize = 32;
inline constexpr uint8_t kAuthenticatedViewFeedbackVersion = 2;
inline constexpr uint8_t kRtcpAppPacketType = 204;
inline constexpr std::array<char, 4> kViewFeedbackName = {'H', 'D', 'B', 'W'};

struct ViewFeedback {
  uint32_t ssrc = 0;
  bool needed = true;
  uint16_t sequence = 0;
};

enum class ViewFeedbackError : uint8_t {
  kNone,
  kNotViewFeedback,  ///< not an APP packet named HDBW: ordinary RTCP, for rtpbin
  kBadLength,        ///< HDBW whose datagram or length field is not 16 bytes
  kBadVersion,  ///< HDBW of an unknown version, or with padding, subtype or reserved flags set,
                ///< or an authenticated one where no key is configured
  kNotAuthenticated,  ///< a key is configured and the message carries no tag (version 1)
  kBadTag,            ///< a key is configured and the tag is not that key's: forged or other key
  kCount
};

std::string_view to_string(ViewFeedbackError e);

/// The tag's key, derived from a stream's SRTP key (see above).
struct ViewFeedbackKey {
  std::array<uint8_t, 32> bytes{};
};
ViewFeedbackKey view_feedback_key(const SrtpKey& srtp);

void write_view_feedback(const ViewFeedback& f, std::span<uint8_t, kViewFeedbackSize> out);
/// The authenticated message (version 2).
void write_view_feedback(const ViewFeedback& f, const ViewFeedbackKey& key,
                         std::span<uint8_t, kAuthenticatedViewFeedbackSize> out);

/// Reads one datagram from an RTCP port. Never reads outside `datagram`. Without a key only
/// version 1 is taken; with one, only version 2 whose tag that key made.
ViewFeedbackError parse_view_feedback(std::span<const uint8_t> datagram, const ViewFeedbackKey* key,
                                      ViewFeedback& out);
inline ViewFeedbackError parse_view_feedback(std::span<const uint8_t> datagram, ViewFeedback& out) {
  return parse_view_feedback(datagram, nullptr, out);
}

}  // namespace hd::drivers
