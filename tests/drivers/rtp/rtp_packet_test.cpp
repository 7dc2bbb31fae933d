// The pure parsers: rtp:// ids, RTP packets and RFC 8285 header extensions (fixed cases, written
// from the RFCs' byte layouts, and a fuzz run of 10^6 mutated packets).
#include "drivers/rtp/rtp_packet.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/rtp_uri.h"

namespace hd::drivers {
namespace {

// RFC 3550 fixed header: V=2, PT 96, seq 0x1234, ts 0x01020304, SSRC 0xAABBCCDD, then `rest`.
std::vector<uint8_t> packet(uint8_t first_byte, std::vector<uint8_t> rest, bool marker = true) {
  const uint8_t header[12] = {
      first_byte, uint8_t((marker ? 0x80 : 0) | 96), 0x12, 0x34, 1, 2, 3, 4, 0xAA, 0xBB, 0xCC,
      0xDD};
  std::vector<uint8_t> p(sizeof header + rest.size());
  for (std::size_t i = 0; i < sizeof header; ++i) p[i] = header[i];
  for (std::size_t i = 0; i < rest.size(); ++i) p[sizeof header + i] = rest[i];
  return p;
}

TEST(RtpUri, ParsesHostAndEvenPort) {
  std::string why;
  const auto a = parse_rtp_uri("rtp://127.0.0.1:5600", why);
  ASSERT_TRUE(a) << why;
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 5600);
  EXPECT_EQ(to_uri(*a), "rtp://127.0.0.1:5600");
  EXPECT_TRUE(parse_rtp_uri("rtp://station-2.lan:40000", why));
}

TEST(RtpUri, RefusesMalformedIdsSayingWhatIsExpected) {
  for (const char* bad : {"rtp://", "rtp://:5600", "rtp://host", "rtp://host:", "rtp://host:5601",
                          "rtp://host:80", "rtp://host:70000", "rtp://host:56x0", "rtp://a b:5600",
                          "udp://host:5600", "rtp://host:-2"}) {
    std::string why;
    EXPECT_FALSE(parse_rtp_uri(bad, why)) << bad;
    EXPECT_NE(why.find("expected rtp://HOST:PORT"), std::string::npos) << bad << ": " << why;
  }
}

TEST(RtpPacket, ParsesTheFixedHeaderAndPayload) {
  const auto p = packet(0x80, {0x65, 0x88, 0x84});
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  EXPECT_EQ(v.payload_type, 96);
  EXPECT_TRUE(v.marker);
  EXPECT_EQ(v.sequence, 0x1234);
  EXPECT_EQ(v.timestamp, 0x01020304u);
  EXPECT_EQ(v.ssrc, 0xAABBCCDDu);
  EXPECT_FALSE(v.has_extension);
  ASSERT_EQ(v.payload.size(), 3u);
  EXPECT_EQ(v.payload[0], 0x65);
}

TEST(RtpPacket, ReadsOneByteElementsAndSkipsPaddingBetweenThem) {
  // RFC 8285 4.2: 0xBEDE, 2 words: id 1 len 2 (3 bytes), a padding byte, id 2 len 1 (2 bytes),
  // one padding byte to the word boundary.
  const auto p =
      packet(0x90, {0xBE, 0xDE, 0x00, 0x02, 0x12, 0xA, 0xB, 0xC, 0x00, 0x21, 0xD, 0xE, 0x77});
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  std::span<const uint8_t> d;
  ASSERT_TRUE(find_rtp_extension(v, 1, d));
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[2], 0xC);
  ASSERT_TRUE(find_rtp_extension(v, 2, d));
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[1], 0xE);
  EXPECT_FALSE(find_rtp_extension(v, 3, d));
  ASSERT_EQ(v.payload.size(), 1u);
  EXPECT_EQ(v.payload[0], 0x77);
}

TEST(RtpPacket, ReadsTwoByteElements) {
  // RFC 8285 4.3: 0x100 + appbits, id 200 length 3, padded to one word... two words.
  const auto p = packet(0x90, {0x10, 0x00, 0x00, 0x02, 200, 3, 1, 2, 3, 0, 0, 0});
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  std::span<const uint8_t> d;
  ASSERT_TRUE(find_rtp_extension(v, 200, d));
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0], 1);
}

TEST(RtpPacket, RefusesEachMalformationByName) {
  RtpPacketView v;
  EXPECT_EQ(parse_rtp_packet(std::vector<uint8_t>(11, 0x80), v), RtpPacketError::kTooShort);
  EXPECT_EQ(parse_rtp_packet(packet(0x40, {}), v), RtpPacketError::kBadVersion);
  EXPECT_EQ(parse_rtp_packet(packet(0x82, {0, 0, 0, 0}), v), RtpPacketError::kCsrcOverrun);
  EXPECT_EQ(parse_rtp_packet(packet(0x90, {0xBE, 0xDE, 0x00}), v),
            RtpPacketError::kExtensionOverrun);
  EXPECT_EQ(parse_rtp_packet(packet(0x90, {0xBE, 0xDE, 0x00, 0x02, 0, 0, 0, 0}), v),
            RtpPacketError::kExtensionOverrun);
  // An element of 4 bytes in a 1-word block that has room for 3 after its header.
  EXPECT_EQ(parse_rtp_packet(packet(0x90, {0xBE, 0xDE, 0x00, 0x01, 0x13, 1, 2, 3}), v),
            RtpPacketError::kBadExtension);
  EXPECT_EQ(parse_rtp_packet(packet(0xA0, {1, 2, 0}), v), RtpPacketError::kBadPadding);
  EXPECT_EQ(parse_rtp_packet(packet(0xA0, {1, 2, 9}), v), RtpPacketError::kBadPadding);
  ASSERT_EQ(parse_rtp_packet(packet(0xA0, {1, 2, 2}), v), RtpPacketError::kNone);
  EXPECT_EQ(v.payload.size(), 1u);
}

TEST(RtpPacket, AMillionMutatedPacketsNeverReadOutsideAndKeepTheirSpansInside) {
  // hybrid-remote's marker packet: two-byte form with camera-state and the calibration element.
  std::vector<uint8_t> calibrated = packet(0x90, {});
  {
    StreamCalibration c;
    c.p_c = core::Pinhole::centred(500.0, 640, 480);
    c.p_c.distortion_count = 4;
    std::array<uint8_t, kCalibrationMaxSize> e{};
    const std::size_t n = write_calibration(c, e);
    const std::vector<uint8_t> one{0x25, 1, 0, 0, 0, 0, 0, 0};
    std::array<uint8_t, 512> block{};
    const std::size_t words =
        to_two_byte_block(one, kCalibrationExtensionId, std::span(e.data(), n), block) / 4;
    for (uint8_t b : {uint8_t(0x10), uint8_t(0x00), uint8_t(words >> 8), uint8_t(words)})
      calibrated.push_back(b);
    calibrated.insert(calibrated.end(), block.begin(), block.begin() + std::ptrdiff_t(4 * words));
    calibrated.push_back(0x65);
  }
  const std::vector<std::vector<uint8_t>> seeds{
      calibrated, packet(0x80, {0x65, 0x88, 0x84, 1, 2, 3}),
      packet(0x90, {0xBE, 0xDE, 0x00, 0x02, 0x12, 0xA, 0xB, 0xC, 0x00, 0x21, 0xD, 0xE, 0x77}),
      packet(0x90, {0x10, 0x00, 0x00, 0x02, 200, 3, 1, 2, 3, 0, 0, 0, 9}),
      packet(0xB1, {1, 2, 3, 4, 0xBE, 0xDE, 0x00, 0x01, 0x10, 5, 0, 0, 7, 2})};
  std::mt19937 rng(12);
  uint64_t accepted = 0;
  for (int i = 0; i < 1'000'000; ++i) {
    std::vector<uint8_t> p = seeds[i % seeds.size()];
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      switch (rng() % 3) {
        case 0:
          p[rng() % p.size()] ^= uint8_t(1u << (rng() % 8));
          break;
        case 1:
          p.resize(rng() % (p.size() + 1));
          if (p.empty()) p.push_back(0x80);
          break;
        default:
          p.push_back(uint8_t(rng()));
      }
    }
    RtpPacketView v;
    if (parse_rtp_packet(p, v) != RtpPacketError::kNone) continue;
    ++accepted;
    const uint8_t* lo = p.data();
    const uint8_t* hi = p.data() + p.size();
    ASSERT_GE(v.payload.data(), lo);
    ASSERT_LE(v.payload.data() + v.payload.size(), hi);
    for (uint8_t id = 1; id < 15; ++id) {
      std::span<const uint8_t> d;
      if (find_rtp_extension(v, id, d)) {
        ASSERT_GE(d.data(), v.extension.data());
        ASSERT_LE(d.data() + d.size(), v.extension.data() + v.extension.size());
      }
    }
    // The stamp and calibration readers take whatever the parser accepted.
    RtpFrameStamp stamp;
    read_frame_stamp(v, stamp);
    std::optional<StreamCalibration> c;
    if (read_packet_calibration(v, stamp.camera, c) == CalibrationError::kNone && c) {
      ASSERT_TRUE(c->p_c.valid() && c->T_world_cam.valid());
    }
  }
  EXPECT_GT(accepted, 10'000u);  // the mutations keep enough packets valid to reach the walker
}

}  // namespace
}  // namespace hd::drivers
