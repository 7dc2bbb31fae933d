// check_h264_payload against RFC 6184 packets laid out by hand: what packetization mode 1 sends
// passes; what rtph264depay 1.22 crashes on (a FU-A of one byte) or errors on (MTAP) is refused.
#include "drivers/rtp/h264_payload.h"

#include <gtest/gtest.h>

#include <vector>

namespace hd::drivers {
namespace {

RtpPacketError check(const std::vector<uint8_t>& p) {
  return check_h264_payload(p);
}

TEST(H264Payload, ModeOnePacketsPass) {
  EXPECT_EQ(check({0x65, 0x88, 0x84}), RtpPacketError::kNone);  // IDR slice, single NAL
  EXPECT_EQ(check({0x41}), RtpPacketError::kNone);              // a one-byte NAL unit
  // STAP-A with SPS (3 bytes) and PPS (2 bytes).
  EXPECT_EQ(check({0x78, 0, 3, 0x67, 0x42, 0x00, 0, 2, 0x68, 0xCE}), RtpPacketError::kNone);
  EXPECT_EQ(check({0x7C, 0x85, 0xB8}), RtpPacketError::kNone);  // FU-A start of an IDR
  EXPECT_EQ(check({0x7C, 0x45, 0x01}), RtpPacketError::kNone);  // FU-A end
}

TEST(H264Payload, WhatTheDepayloaderMishandlesIsRefusedByName) {
  EXPECT_EQ(check({}), RtpPacketError::kH264Empty);
  EXPECT_EQ(check({0xE5, 0x00}), RtpPacketError::kH264Empty);        // forbidden bit
  EXPECT_EQ(check({0x7C}), RtpPacketError::kH264BadFragment);        // FU-A of 1 byte: a crash
  EXPECT_EQ(check({0x7C, 0x05}), RtpPacketError::kH264BadFragment);  // no data
  EXPECT_EQ(check({0x7C, 0xC5, 0x01}), RtpPacketError::kH264BadFragment);      // start and end
  EXPECT_EQ(check({0x78, 0, 9, 0x67}), RtpPacketError::kH264BadAggregate);     // size past the end
  EXPECT_EQ(check({0x78, 0, 0, 0x67}), RtpPacketError::kH264BadAggregate);     // size 0
  EXPECT_EQ(check({0x78, 0, 1, 0x67, 0}), RtpPacketError::kH264BadAggregate);  // a stray byte
  for (uint8_t type : {0, 25, 26, 27, 29, 30, 31})
    EXPECT_EQ(check({uint8_t(0x60 | type), 0, 0, 0, 0, 0, 0}), RtpPacketError::kH264BadType)
        << int(type);
  EXPECT_EQ(to_string(RtpPacketError::kH264BadFragment),
            "H.264 FU-A too short or both start and end");
}

// RFC 4588: a retransmission's payload is the original sequence number, then the original
// payload; read as H.264 from its first byte, OSN 0x0000 would be NAL type 0 and refused.
TEST(H264Payload, ARetransmissionIsCheckedAfterItsOriginalSequenceNumber) {
  const std::vector<uint8_t> fu_a_start{0x00, 0x00, 0x7C, 0x85, 0xB8};
  EXPECT_EQ(check_h264_rtx_payload(fu_a_start), RtpPacketError::kNone);
  EXPECT_EQ(check_h264_payload(fu_a_start), RtpPacketError::kH264BadType);
  const std::vector<uint8_t> stap_a{0x12, 0x34, 0x78, 0, 3, 0x67, 0x42, 0x00, 0, 2, 0x68, 0xCE};
  EXPECT_EQ(check_h264_rtx_payload(stap_a), RtpPacketError::kNone);
  const std::vector<uint8_t> short_fu_a{0x00, 0x07, 0x7C};  // the crash case, behind an OSN
  EXPECT_EQ(check_h264_rtx_payload(short_fu_a), RtpPacketError::kH264BadFragment);
  for (std::size_t n = 0; n < 3; ++n)
    EXPECT_EQ(check_h264_rtx_payload(std::span(fu_a_start).first(n)), RtpPacketError::kH264Empty)
        << n;
}

}  // namespace
}  // namespace hd::drivers
