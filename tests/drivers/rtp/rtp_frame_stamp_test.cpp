// The capture-time and camera-state stamp of hybrid-remote's packets (RFC 6051 ntp-64 and this
// project's camera-state element), read from bytes laid out by hand after the RFCs.
#include "drivers/rtp/rtp_frame_stamp.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <random>
#include <vector>

namespace hd::drivers {
namespace {

// A packet whose one-byte extension block holds `elements` (padded to whole words).
std::vector<uint8_t> packet_with(const std::vector<uint8_t>& elements) {
  std::vector<uint8_t> block = elements;
  while (block.size() % 4 != 0) block.push_back(0);
  std::vector<uint8_t> p{0x90, 96, 0, 1, 0,    0,    0, 9,
                         0,    0,  0, 7, 0xBE, 0xDE, 0, static_cast<uint8_t>(block.size() / 4)};
  for (uint8_t b : block) p.push_back(b);
  p.push_back(0x65);
  return p;
}

TEST(RtpFrameStamp, Ntp64IsSecondsSince1900In32Dot32) {
  // 2026-12-02T00:00:00.5Z = Unix 1796169600.5 s; NTP seconds = that + 2208988800.
  const int64_t unix_ns = 1'796'169'600'500'000'000LL;
  const uint64_t ntp = unix_ns_to_ntp64(unix_ns);
  EXPECT_EQ(ntp >> 32, 1'796'169'600ull + 2'208'988'800ull);
  EXPECT_EQ(ntp & 0xFFFFFFFFu, 0x80000000u);  // half a second
  EXPECT_EQ(*ntp64_to_unix_ns(ntp), unix_ns);
  EXPECT_FALSE(ntp64_to_unix_ns(0));  // rtphdrextntp64 writes 0 when it has no time
  std::mt19937_64 rng(3);
  // Round trip within the 0.23 ns of one fraction step, over NTP era 0 (to 2036-02-07).
  for (int i = 0; i < 10000; ++i) {
    const int64_t t = int64_t(rng() % 2'000'000'000'000'000'000ull);
    EXPECT_LE(std::llabs(*ntp64_to_unix_ns(unix_ns_to_ntp64(t)) - t), 1);
  }
}

TEST(RtpFrameStamp, ReadsBothElements) {
  const uint64_t ntp = unix_ns_to_ntp64(1'000'000'000'123'456'789LL);
  std::vector<uint8_t> e{uint8_t((kNtp64ExtensionId << 4) | 7)};
  for (int i = 7; i >= 0; --i) e.push_back(uint8_t(ntp >> (8 * i)));
  uint8_t state[kCameraStateSize];
  write_camera_state({3, 0x01020304}, std::span<uint8_t, kCameraStateSize>(state));
  e.push_back(uint8_t((kCameraStateExtensionId << 4) | 5));
  for (uint8_t b : state) e.push_back(b);
  const auto p = packet_with(e);
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  RtpFrameStamp s;
  ASSERT_EQ(read_frame_stamp(v, s), StampError::kNone);
  EXPECT_EQ(*s.capture_unix_ns, 1'000'000'000'123'456'789LL);
  ASSERT_TRUE(s.camera);
  EXPECT_EQ(s.camera->camera_index, 3);
  EXPECT_EQ(s.camera->calibration_revision, 0x01020304u);
}

TEST(RtpFrameStamp, ReadsTheSenderStages) {
  const uint64_t ntp = unix_ns_to_ntp64(1'000'000'000'123'456'789LL);
  std::vector<uint8_t> e{uint8_t((kNtp64ExtensionId << 4) | 7)};
  for (int i = 7; i >= 0; --i) e.push_back(uint8_t(ntp >> (8 * i)));
  uint8_t stages[kSenderStagesSize];
  write_sender_stages({4'321, 0x01020304, 7, 250}, std::span<uint8_t, kSenderStagesSize>(stages));
  // By hand: version 1, count 7, then big endian 4321 = 0x10E1, 0x01020304, 250 = 0xFA.
  const uint8_t expected[] = {1, 7, 0, 0, 0x10, 0xE1, 1, 2, 3, 4, 0, 0, 0, 0xFA};
  EXPECT_TRUE(std::equal(std::begin(stages), std::end(stages), std::begin(expected)));
  e.push_back(uint8_t((kSenderStagesExtensionId << 4) | 13));
  for (uint8_t b : stages) e.push_back(b);
  const auto p = packet_with(e);
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  RtpFrameStamp s;
  ASSERT_EQ(read_frame_stamp(v, s), StampError::kNone);
  ASSERT_TRUE(s.stages);
  EXPECT_EQ(s.stages->encoded_us, 4'321u);
  EXPECT_EQ(s.stages->sent_us, 0x01020304u);
  EXPECT_EQ(s.stages->round_trip_count, 7);
  EXPECT_EQ(s.stages->round_trip_us, 250u);
  EXPECT_FALSE(s.camera);
}

TEST(RtpFrameStamp, RefusesBadValuesByName) {
  RtpPacketView v;
  RtpFrameStamp s;
  auto read = [&](const std::vector<uint8_t>& e) {
    const auto p = packet_with(e);
    EXPECT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
    return read_frame_stamp(v, s);
  };
  EXPECT_EQ(read({0x31, 1, 2}), StampError::kNoNtp);             // only an unknown element
  EXPECT_EQ(read({0x13, 1, 2, 3, 4}), StampError::kBadNtpSize);  // 4 bytes
  EXPECT_EQ(read({0x17, 0, 0, 0, 0, 0, 0, 0, 0}), StampError::kZeroNtp);
  EXPECT_EQ(read({0x22, 1, 2, 3}), StampError::kBadStateSize);
  EXPECT_EQ(read({0x25, 9, 0, 0, 0, 0, 1}), StampError::kBadStateVersion);
  EXPECT_EQ(read({0x42, 1, 0, 0}), StampError::kBadStagesSize);
  EXPECT_EQ(read({0x4D, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}), StampError::kBadStagesVersion);
}

}  // namespace
}  // namespace hd::drivers
