#include "drivers/rtp/h264_payload.h"

namespace hd::drivers {

RtpPacketError check_h264_payload(std::span<const uint8_t> payload) {
  if (payload.empty() || (payload[0] & 0x80) != 0) return RtpPacketError::kH264Empty;
  const int type = payload[0] & 0x1F;
  if (type >= 1 && type <= 23) return RtpPacketError::kNone;
  if (type == 24) {  // STAP-A: [size u16][NAL unit] ...
    std::size_t at = 1;
    if (payload.size() < 4) return RtpPacketError::kH264BadAggregate;
    while (at < payload.size()) {
      if (payload.size() - at < 2) return RtpPacketError::kH264BadAggregate;
      const std::size_t size = (std::size_t{payload[at]} << 8) | payload[at + 1];
      at += 2;
      if (size == 0 || size > payload.size() - at) return RtpPacketError::kH264BadAggregate;
      at += size;
    }
    return RtpPacketError::kNone;
  }
  if (type == 28) {  // FU-A: indicator, header (S E R type), data
    if (payload.size() < 3) return RtpPacketError::kH264BadFragment;
    if ((payload[1] & 0xC0) == 0xC0) return RtpPacketError::kH264BadFragment;
    return RtpPacketError::kNone;
  }
  return RtpPacketError::kH264BadType;  // 0, 25 (STAP-B), 26/27 (MTAP), 29 (FU-B), 30, 31
}

RtpPacketError check_h264_rtx_payload(std::span<const uint8_t> payload) {
  if (payload.size() < 3) return RtpPacketError::kH264Empty;  // OSN and at least one NAL byte
  return check_h264_payload(payload.subspan(2));
}

}  // namespace hd::drivers
