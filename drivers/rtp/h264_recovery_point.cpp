// scan_h264_access_unit and the SEI recovery point parser (H.264 7.3.2.3, D.1.8): NAL units split
// by start code or length, emulation prevention removed, SEI messages walked by type and size.
#include "drivers/rtp/h264_recovery_point.h"

#include <vector>

namespace hd::drivers {
namespace {

constexpr uint8_t kSeiNal = 6, kIdrNal = 5;
constexpr uint32_t kRecoveryPointPayload = 6;
constexpr uint32_t kMaxRecoveryFrameCnt = 65535;  // < MaxFrameNum, at most 2^16

// The RBSP of a NAL unit's payload: every 00 00 03 loses its 03 (7.4.1).
std::vector<uint8_t> unescape(std::span<const uint8_t> payload) {
  std::vector<uint8_t> rbsp;
  rbsp.reserve(payload.size());
  int zeros = 0;
  for (uint8_t b : payload) {
    if (zeros >= 2 && b == 3) {
      zeros = 0;
      continue;
    }
    zeros = b == 0 ? zeros + 1 : 0;
    rbsp.push_back(b);
  }
  return rbsp;
}

// ue(v) (9.1) from bits of `bytes`; nullopt past the end or beyond 32 bits of value.
std::optional<uint32_t> read_ue(std::span<const uint8_t> bytes) {
  std::size_t bit = 0;
  auto next = [&]() -> int {
    if (bit >= bytes.size() * 8) return -1;
    const int v = (bytes[bit / 8] >> (7 - bit % 8)) & 1;
    ++bit;
    return v;
  };
  int zeros = 0;
  for (int b = next(); b != 1; b = next()) {
    if (b < 0 || ++zeros > 31) return std::nullopt;
  }
  uint64_t rest = 0;
  for (int i = 0; i < zeros; ++i) {
    const int b = next();
    if (b < 0) return std::nullopt;
    rest = (rest << 1) | uint64_t(b);
  }
  const uint64_t v = (uint64_t{1} << zeros) - 1 + rest;
  return v > UINT32_MAX ? std::nullopt : std::optional<uint32_t>(uint32_t(v));
}

// payloadType / payloadSize (7.3.2.3.1): 0xFF bytes each add 255, then the last byte.
bool read_sei_number(std::span<const uint8_t> rbsp, std::size_t& at, uint32_t& value) {
  value = 0;
  while (at < rbsp.size() && rbsp[at] == 0xFF) {
    value += 255;
    ++at;
    if (value > (1u << 24)) return false;  // no SEI is this long: garbage
  }
  if (at >= rbsp.size()) return false;
  value += rbsp[at++];
  return true;
}

}  // namespace

std::optional<uint32_t> sei_recovery_frame_cnt(std::span<const uint8_t> nal, bool* malformed) {
  auto fail = [&] {
    if (malformed != nullptr) *malformed = true;
    return std::nullopt;
  };
  if (nal.empty() || (nal[0] & 0x1F) != kSeiNal) return std::nullopt;
  std::vector<uint8_t> rbsp = unescape(nal.subspan(1));
  // trailing_zero_8bits (the leading zero of a next 4-byte start code) are not the SEI's.
  while (!rbsp.empty() && rbsp.back() == 0) rbsp.pop_back();
  std::size_t at = 0;
  // Messages until the rbsp_trailing_bits (a lone 0x80) or the end.
  while (at < rbsp.size() && !(rbsp[at] == 0x80 && at + 1 == rbsp.size())) {
    uint32_t type = 0, size = 0;
    if (!read_sei_number(rbsp, at, type) || !read_sei_number(rbsp, at, size)) return fail();
    if (size > rbsp.size() - at) return fail();
    const std::span<const uint8_t> payload(rbsp.data() + at, size);
    if (type == kRecoveryPointPayload) {
      const std::optional<uint32_t> cnt = read_ue(payload);
      if (!cnt || *cnt > kMaxRecoveryFrameCnt) return fail();
      return cnt;
    }
    at += size;
  }
  return std::nullopt;
}

bool h264_payload_starts_picture(std::span<const uint8_t> payload) {
  // A NAL unit's header byte and the byte after it (for a slice, first_mb_in_slice's ue(v) is
  // "1", i.e. 0, exactly when that byte's top bit is set).
  auto starts = [](uint8_t header, std::optional<uint8_t> next) {
    const uint8_t type = header & 0x1F;
    if (type >= kSeiNal && type <= 9) return true;  // SEI, SPS, PPS, AUD
    if (type >= 1 && type <= kIdrNal) return next.has_value() && (*next & 0x80) != 0;
    return false;
  };
  auto byte = [&](std::size_t i) {
    return i < payload.size() ? std::optional<uint8_t>(payload[i]) : std::nullopt;
  };
  if (payload.empty()) return false;
  const uint8_t type = payload[0] & 0x1F;
  if (type == 24) return payload.size() > 3 && starts(payload[3], byte(4));  // STAP-A: size, NAL
  if (type == 28)  // FU-A: the indicator, then the FU header with S (start) and the NAL's type
    return payload.size() > 1 && (payload[1] & 0x80) != 0 &&
           starts(uint8_t((payload[0] & 0xE0) | (payload[1] & 0x1F)), byte(2));
  return starts(payload[0], byte(1));
}

H264AccessUnitInfo scan_h264_access_unit(std::span<const uint8_t> au, H264Framing framing) {
  H264AccessUnitInfo info;
  auto look_at = [&](std::span<const uint8_t> nal) {
    if (nal.empty()) return;
    const uint8_t type = nal[0] & 0x1F;
    if (type == kIdrNal) info.idr = true;
    if (type == kSeiNal && !info.recovery_frame_cnt)
      info.recovery_frame_cnt = sei_recovery_frame_cnt(nal, &info.malformed);
  };
  if (framing == H264Framing::kAvc) {
    std::size_t at = 0;
    while (at < au.size()) {
      if (au.size() - at < 4) {
        info.malformed = true;
        break;
      }
      const uint32_t len = uint32_t(au[at]) << 24 | uint32_t(au[at + 1]) << 16 |
                           uint32_t(au[at + 2]) << 8 | uint32_t(au[at + 3]);
      at += 4;
      if (len > au.size() - at) {
        info.malformed = true;
        break;
      }
      look_at(au.subspan(at, len));
      at += len;
    }
    return info;
  }
  // Annex B: a NAL unit runs from after one 00 00 01 to the next (whose leading zero, if it is a
  // 4-byte start code, is trailing_zero_8bits: harmless, the SEI walk stops at its trailing bits).
  std::size_t start = SIZE_MAX;
  for (std::size_t i = 0; i + 2 < au.size(); ++i) {
    if (au[i] != 0 || au[i + 1] != 0 || au[i + 2] != 1) continue;
    if (start != SIZE_MAX) look_at(au.subspan(start, i - start));
    start = i + 3;
    i += 2;
  }
  if (start != SIZE_MAX && start < au.size()) look_at(au.subspan(start));
  if (start == SIZE_MAX && !au.empty()) info.malformed = true;  // no start code at all
  return info;
}

}  // namespace hd::drivers
