#include "drivers/rtp/rtp_packet.h"

namespace hd::drivers {
namespace {

uint16_t be16(const uint8_t* p) {
  return static_cast<uint16_t>((p[0] << 8) | p[1]);
}
uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}

bool one_byte(uint16_t profile) {
  return profile == 0xBEDE;
}
bool two_byte(uint16_t profile) {
  return (profile & 0xFFF0) == 0x1000;
}

// Walks the RFC 8285 elements of `block`; calls f(id, data) for each until it returns true.
// Returns false when an element is malformed.
template <class F>
bool walk_elements(uint16_t profile, std::span<const uint8_t> block, F f) {
  std::size_t i = 0;
  while (i < block.size()) {
    if (block[i] == 0) {  // padding between elements
      ++i;
      continue;
    }
    uint8_t id = 0;
    std::size_t len = 0;
    if (one_byte(profile)) {
      id = block[i] >> 4;
      len = (block[i] & 0x0F) + 1u;
      if (id == 15) return true;  // RFC 8285 4.2: stop processing, the rest is not elements
      i += 1;
    } else {
      if (i + 2 > block.size()) return false;
      id = block[i];
      len = block[i + 1];
      i += 2;
    }
    if (i + len > block.size()) return false;
    if (f(id, block.subspan(i, len))) return true;
    i += len;
  }
  return true;
}

}  // namespace

std::string_view to_string(RtpPacketError e) {
  switch (e) {
    case RtpPacketError::kNone:
      return "ok";
    case RtpPacketError::kTooShort:
      return "shorter than an RTP header";
    case RtpPacketError::kBadVersion:
      return "not RTP version 2";
    case RtpPacketError::kCsrcOverrun:
      return "CSRC list past the end";
    case RtpPacketError::kExtensionOverrun:
      return "header extension past the end";
    case RtpPacketError::kBadPadding:
      return "bad padding";
    case RtpPacketError::kBadExtension:
      return "malformed RFC 8285 element";
    case RtpPacketError::kOtherPayloadType:
      return "another payload type than the stream's";
    case RtpPacketError::kOtherSsrc:
      return "another SSRC while the stream's is live";
    case RtpPacketError::kSequenceJump:
      return "sequence number jumps implausibly for the stream";
    case RtpPacketError::kRtpTimeJump:
      return "RTP time jumps implausibly for the stream";
    case RtpPacketError::kH264Empty:
      return "H.264 payload empty or its forbidden bit set";
    case RtpPacketError::kH264BadType:
      return "H.264 NAL unit type undefined or not of packetization mode 1";
    case RtpPacketError::kH264BadAggregate:
      return "H.264 STAP-A sizes do not fill the packet";
    case RtpPacketError::kH264BadFragment:
      return "H.264 FU-A too short or both start and end";
    case RtpPacketError::kFecTooShort:
      return "ULP FEC packet shorter than its FEC and level headers";
    case RtpPacketError::kCount:
      break;
  }
  return "unknown";
}

RtpPacketError parse_rtp_packet(std::span<const uint8_t> packet, RtpPacketView& out) {
  out = {};
  if (packet.size() < 12) return RtpPacketError::kTooShort;
  const uint8_t* b = packet.data();
  if ((b[0] >> 6) != 2) return RtpPacketError::kBadVersion;
  const bool padding = (b[0] & 0x20) != 0, extension = (b[0] & 0x10) != 0;
  const std::size_t csrc_count = b[0] & 0x0F;
  out.marker = (b[1] & 0x80) != 0;
  out.payload_type = b[1] & 0x7F;
  out.sequence = be16(b + 2);
  out.timestamp = be32(b + 4);
  out.ssrc = be32(b + 8);
  std::size_t at = 12 + 4 * csrc_count;
  if (at > packet.size()) return RtpPacketError::kCsrcOverrun;
  if (extension) {
    if (at + 4 > packet.size()) return RtpPacketError::kExtensionOverrun;
    out.extension_profile = be16(b + at);
    const std::size_t words = be16(b + at + 2);
    at += 4;
    if (at + 4 * words > packet.size()) return RtpPacketError::kExtensionOverrun;
    out.has_extension = true;
    out.extension = packet.subspan(at, 4 * words);
    at += 4 * words;
    if (one_byte(out.extension_profile) || two_byte(out.extension_profile)) {
      const bool ok = walk_elements(out.extension_profile, out.extension,
                                    [](uint8_t, std::span<const uint8_t>) { return false; });
      if (!ok) return RtpPacketError::kBadExtension;
    }
  }
  std::size_t end = packet.size();
  if (padding) {
    const std::size_t pad = b[packet.size() - 1];
    if (pad == 0 || pad > end - at) return RtpPacketError::kBadPadding;
    end -= pad;
  }
  out.payload = packet.subspan(at, end - at);
  return RtpPacketError::kNone;
}

bool find_rtp_extension(const RtpPacketView& p, uint8_t id, std::span<const uint8_t>& data) {
  if (!p.has_extension || !(one_byte(p.extension_profile) || two_byte(p.extension_profile)))
    return false;
  bool found = false;
  walk_elements(p.extension_profile, p.extension, [&](uint8_t e, std::span<const uint8_t> d) {
    if (e != id) return false;
    data = d;
    found = true;
    return true;
  });
  return found;
}

std::size_t to_two_byte_block(std::span<const uint8_t> one_byte_block, uint8_t extra_id,
                              std::span<const uint8_t> extra, std::span<uint8_t> out) {
  if (extra_id == 0 || extra.size() > 255) return 0;
  std::size_t at = 0;
  bool fits = true;
  auto put = [&](uint8_t id, std::span<const uint8_t> d) {
    if (at + 2 + d.size() > out.size()) {
      fits = false;
      return true;
    }
    out[at] = id;
    out[at + 1] = static_cast<uint8_t>(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) out[at + 2 + i] = d[i];
    at += 2 + d.size();
    return false;
  };
  if (!walk_elements(0xBEDE, one_byte_block, put)) return 0;
  if (!fits) return 0;
  put(extra_id, extra);
  if (!fits) return 0;
  while (at % 4 != 0) {
    if (at >= out.size()) return 0;
    out[at++] = 0;
  }
  return at;
}

}  // namespace hd::drivers
