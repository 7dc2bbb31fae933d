#pragma once
// The station's "which cameras it uses" feedback to the remote site (bandwidth follows the view,
// issue 12 item 5): one RTCP APP packet (RFC 3550 section 6.7) per camera stream, pure writer and
// parser.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

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
inline constexpr std::size_t kViewFeedbackSize = 16;
inline constexpr uint8_t kViewFeedbackVersion = 1;
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
  kBadVersion,       ///< HDBW of an unknown version, or with padding, subtype or reserved flags set
  kCount
};

std::string_view to_string(ViewFeedbackError e);

void write_view_feedback(const ViewFeedback& f, std::span<uint8_t, kViewFeedbackSize> out);

/// Reads one datagram from an RTCP port. Never reads outside `datagram`.
ViewFeedbackError parse_view_feedback(std::span<const uint8_t> datagram, ViewFeedback& out);

}  // namespace hd::drivers
