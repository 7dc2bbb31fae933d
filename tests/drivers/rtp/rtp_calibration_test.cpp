// The calibration element (id 3, two-byte form): p_c with distortion and P_c, byte for byte from
// the layout in docs/network.md, the round trip through a packet, every refusal by name, and a
// fuzz run of mutated elements and packets.
#include "drivers/rtp/rtp_calibration.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "core/opencv_pixels.h"

namespace hd::drivers {
namespace {

// OpenCV's published calibration of opencv-left (README table) with a tilted pose.
StreamCalibration example(int distortion_count = 5) {
  core::OpenCvIntrinsics k;
  k.fx = 535.9;
  k.fy = 536.1;
  k.cx = 342.3;
  k.cy = 235.6;
  k.width = 640;
  k.height = 480;
  k.distortion = {-0.265, -0.0467, 0.00183, -0.000315, 0.252, 0.01, -0.02, 0.03};
  k.distortion_count = distortion_count;
  for (int i = distortion_count; i < 8; ++i) k.distortion[std::size_t(i)] = 0.0;
  StreamCalibration c;
  c.camera_index = 2;
  c.revision = 0x01020304;
  c.p_c = core::from_opencv(k);
  c.T_world_cam.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  c.T_world_cam.t = {0.25, -1.5, 2.125};
  return c;
}

double be_f64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return std::bit_cast<double>(v);
}

// An RTP packet whose two-byte extension block holds `elements`.
std::vector<uint8_t> two_byte_packet(const std::vector<uint8_t>& elements, bool marker = true) {
  std::vector<uint8_t> block = elements;
  while (block.size() % 4 != 0) block.push_back(0);
  std::vector<uint8_t> p{0x90,
                         uint8_t((marker ? 0x80 : 0) | 96),
                         0,
                         1,
                         0,
                         0,
                         0,
                         9,
                         0,
                         0,
                         0,
                         7,
                         0x10,
                         0x00,
                         uint8_t(block.size() / 4 >> 8),
                         uint8_t(block.size() / 4)};
  for (uint8_t b : block) p.push_back(b);
  p.push_back(0x65);
  return p;
}

std::vector<uint8_t> element(const StreamCalibration& c) {
  std::array<uint8_t, kCalibrationMaxSize> b{};
  const std::size_t n = write_calibration(c, b);
  return {b.begin(), b.begin() + std::ptrdiff_t(n)};
}

TEST(RtpCalibration, TheLayoutIsTheDocumentedOneWithOpenCvsPrincipalPoint) {
  const StreamCalibration c = example(5);
  const auto e = element(c);
  ASSERT_EQ(e.size(), 180u);  // 140 + 8 * 5
  EXPECT_EQ(e[0], 1);         // version
  EXPECT_EQ(e[1], 2);         // camera index
  EXPECT_EQ((e[2] << 24) | (e[3] << 16) | (e[4] << 8) | e[5], 0x01020304);
  EXPECT_EQ((e[6] << 8) | e[7], 640);
  EXPECT_EQ((e[8] << 8) | e[9], 480);
  EXPECT_EQ(e[10], 5);
  EXPECT_EQ(be_f64(&e[12]), 535.9);
  EXPECT_EQ(be_f64(&e[28]), 342.3);  // the file's (OpenCV's) cx, not core's + 0.5
  EXPECT_EQ(be_f64(&e[36]), 235.6);
  EXPECT_EQ(be_f64(&e[44]), -0.265);                 // k1
  EXPECT_EQ(be_f64(&e[44 + 4 * 8]), 0.252);          // k3
  EXPECT_EQ(be_f64(&e[84]), c.T_world_cam.R(0, 0));  // R row-major after the coefficients
  EXPECT_EQ(be_f64(&e[84 + 8]), c.T_world_cam.R(0, 1));
  EXPECT_EQ(be_f64(&e[156]), 0.25);  // t
  EXPECT_EQ(be_f64(&e[172]), 2.125);
}

TEST(RtpCalibration, RoundTripsBitForBitThroughATwoBytePacket) {
  for (int n : {0, 4, 5, 8}) {
    const StreamCalibration c = example(n);
    const auto e = element(c);
    ASSERT_EQ(e.size(), calibration_element_size(n));
    std::vector<uint8_t> els{kCalibrationExtensionId, uint8_t(e.size())};
    els.insert(els.end(), e.begin(), e.end());
    const auto p = two_byte_packet(els);
    RtpPacketView v;
    ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
    std::optional<StreamCalibration> got;
    ASSERT_EQ(read_packet_calibration(v, CameraStateStamp{2, 0x01020304}, got),
              CalibrationError::kNone);
    ASSERT_TRUE(got);
    EXPECT_EQ(got->camera_index, 2);
    EXPECT_EQ(got->revision, 0x01020304u);
    EXPECT_EQ(got->p_c.width, 640);
    EXPECT_EQ(got->p_c.height, 480);
    EXPECT_EQ(got->p_c.distortion_count, n);
    EXPECT_EQ(got->p_c.fx, c.p_c.fx);
    EXPECT_EQ(got->p_c.fy, c.p_c.fy);
    // cx travels as OpenCV's number: - 0.5 and + 0.5 again, exact for these values.
    EXPECT_EQ(got->p_c.cx, c.p_c.cx);
    EXPECT_EQ(got->p_c.cy, c.p_c.cy);
    for (int i = 0; i < 8; ++i)
      EXPECT_EQ(got->p_c.distortion[std::size_t(i)], c.p_c.distortion[std::size_t(i)]);
    EXPECT_EQ(got->T_world_cam.R, c.T_world_cam.R);
    EXPECT_EQ(got->T_world_cam.t, c.T_world_cam.t);
  }
}

TEST(RtpCalibration, APacketWithoutTheElementHasNone) {
  const auto p = two_byte_packet({9, 2, 1, 2});
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  std::optional<StreamCalibration> got;
  EXPECT_EQ(read_packet_calibration(v, std::nullopt, got), CalibrationError::kNone);
  EXPECT_FALSE(got);
}

TEST(RtpCalibration, RefusesEachBadValueByName) {
  auto read = [](std::vector<uint8_t> e) {
    StreamCalibration out;
    return read_calibration(e, out);
  };
  const auto good = element(example(5));
  auto with = [&](std::size_t at, double v) {
    auto e = good;
    const uint64_t u = std::bit_cast<uint64_t>(v);
    for (int i = 0; i < 8; ++i) e[at + std::size_t(i)] = uint8_t(u >> (56 - 8 * i));
    return e;
  };
  EXPECT_EQ(read(good), CalibrationError::kNone);
  EXPECT_EQ(read({good.begin(), good.begin() + 100}), CalibrationError::kBadSize);
  auto e = good;
  e.push_back(0);
  EXPECT_EQ(read(e), CalibrationError::kBadSize);
  e = good;
  e[0] = 2;
  EXPECT_EQ(read(e), CalibrationError::kBadVersion);
  e = good;
  e[10] = 3;
  EXPECT_EQ(read(e), CalibrationError::kBadDistortionCount);
  e = good;
  e[10] = 4;  // says 4 coefficients but has the bytes of 5
  EXPECT_EQ(read(e), CalibrationError::kBadSize);
  EXPECT_EQ(read(with(12, NAN)), CalibrationError::kNotFinite);              // fx
  EXPECT_EQ(read(with(44 + 8, INFINITY)), CalibrationError::kNotFinite);     // k2
  EXPECT_EQ(read(with(156 + 16, -INFINITY)), CalibrationError::kNotFinite);  // t.z
  EXPECT_EQ(read(with(12, 0.0)), CalibrationError::kBadFocalLength);
  EXPECT_EQ(read(with(20, -536.0)), CalibrationError::kBadFocalLength);
  e = good;
  e[6] = e[7] = 0;
  EXPECT_EQ(read(e), CalibrationError::kBadImageSize);
  EXPECT_EQ(read(with(84, 2.0)), CalibrationError::kNotRotation);  // R(0,0) scaled
  // A mirror (det -1) is no rotation either.
  StreamCalibration m = example(5);
  const auto mirrored = [&] {
    auto x = good;
    for (int col = 0; col < 3; ++col) {
      const double v = -m.T_world_cam.R(0, col);
      const uint64_t u = std::bit_cast<uint64_t>(v);
      for (int i = 0; i < 8; ++i)
        x[84 + 8 * std::size_t(col) + std::size_t(i)] = uint8_t(u >> (56 - 8 * i));
    }
    return x;
  }();
  EXPECT_EQ(read(mirrored), CalibrationError::kNotRotation);
  // Inconsistent with the packet's camera-state: another camera or another revision.
  std::vector<uint8_t> els{kCalibrationExtensionId, uint8_t(good.size())};
  els.insert(els.end(), good.begin(), good.end());
  const auto p = two_byte_packet(els);
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  std::optional<StreamCalibration> got;
  EXPECT_EQ(read_packet_calibration(v, CameraStateStamp{3, 0x01020304}, got),
            CalibrationError::kInconsistentState);
  EXPECT_EQ(read_packet_calibration(v, CameraStateStamp{2, 7}, got),
            CalibrationError::kInconsistentState);
  EXPECT_FALSE(got);
  EXPECT_NE(to_string(CalibrationError::kNotRotation).find("rotation"), std::string_view::npos);
}

TEST(RtpCalibration, RefusesToWriteWhatCannotBeSent) {
  std::array<uint8_t, kCalibrationMaxSize> b{};
  StreamCalibration c = example(5);
  c.p_c.fx = 0.0;
  EXPECT_EQ(write_calibration(c, b), 0u);
  c = example(5);
  c.p_c.distortion_count = 6;
  EXPECT_EQ(write_calibration(c, b), 0u);
  c = example(5);
  c.T_world_cam.R(0, 0) = 3.0;
  EXPECT_EQ(write_calibration(c, b), 0u);
  c = example(5);
  c.p_c.width = 70000;
  EXPECT_EQ(write_calibration(c, b), 0u);
}

TEST(RtpCalibration, OneByteElementsAreRewrittenInTheTwoByteFormWithTheCalibration) {
  // RFC 8285 4.2 one-byte block: id 1 (8 bytes), padding, id 2 (6 bytes), padding to a word.
  const std::vector<uint8_t> one{0x17, 1, 2, 3, 4, 5, 6, 7, 8, 0, 0x25, 1, 1, 9, 0, 0, 0, 0, 0, 0};
  const auto cal = element(example(8));
  std::array<uint8_t, 512> out{};
  const std::size_t n = to_two_byte_block(one, kCalibrationExtensionId, cal, out);
  ASSERT_EQ(n % 4, 0u);
  ASSERT_EQ(n, ((2 + 8) + (2 + 6) + (2 + cal.size()) + 3) / 4 * 4);
  const auto p = two_byte_packet({out.begin(), out.begin() + std::ptrdiff_t(n)});
  RtpPacketView v;
  ASSERT_EQ(parse_rtp_packet(p, v), RtpPacketError::kNone);
  std::span<const uint8_t> d;
  ASSERT_TRUE(find_rtp_extension(v, 1, d));
  EXPECT_EQ(std::vector<uint8_t>(d.begin(), d.end()),
            (std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}));
  RtpFrameStamp stamp;
  read_frame_stamp(v, stamp);  // ntp-64 of these bytes is before 1970: only the state counts
  ASSERT_TRUE(stamp.camera);
  EXPECT_EQ(stamp.camera->camera_index, 1);
  std::optional<StreamCalibration> got;
  // The state says camera 1 revision 0x09000000: inconsistent with the element (2, 0x01020304).
  EXPECT_EQ(read_packet_calibration(v, stamp.camera, got), CalibrationError::kInconsistentState);
  EXPECT_EQ(read_packet_calibration(v, std::nullopt, got), CalibrationError::kNone);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->p_c.distortion_count, 8);
  // Malformed input, an oversized element, no room: nothing written.
  EXPECT_EQ(to_two_byte_block(std::vector<uint8_t>{0x17, 1, 2}, 3, cal, out), 0u);
  EXPECT_EQ(to_two_byte_block(one, 3, std::vector<uint8_t>(256, 1), out), 0u);
  std::array<uint8_t, 64> small{};
  EXPECT_EQ(to_two_byte_block(one, 3, cal, small), 0u);
}

TEST(RtpCalibration, AMillionMutatedElementsAndPacketsAreRefusedOrReadInRange) {
  const auto good = element(example(5));
  std::vector<uint8_t> els{kCalibrationExtensionId, uint8_t(good.size())};
  els.insert(els.end(), good.begin(), good.end());
  const auto seed = two_byte_packet(els);
  std::mt19937 rng(31);
  uint64_t accepted = 0, refused = 0;
  for (int i = 0; i < 1'000'000; ++i) {
    std::vector<uint8_t> p = seed;
    const int edits = 1 + int(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      switch (rng() % 4) {
        case 0:
        case 1:
          p[rng() % p.size()] ^= uint8_t(1u << (rng() % 8));
          break;
        case 2:
          p.resize(rng() % (p.size() + 1));
          if (p.empty()) p.push_back(0x80);
          break;
        default:
          p.push_back(uint8_t(rng()));
      }
    }
    RtpPacketView v;
    if (parse_rtp_packet(p, v) != RtpPacketError::kNone) continue;
    std::optional<StreamCalibration> got;
    RtpFrameStamp stamp;
    read_frame_stamp(v, stamp);
    const CalibrationError e = read_packet_calibration(v, stamp.camera, got);
    if (e != CalibrationError::kNone) {
      ++refused;
      ASSERT_FALSE(got);
      continue;
    }
    if (!got) continue;
    ++accepted;
    // Whatever is accepted is usable as it is.
    ASSERT_TRUE(got->p_c.valid());
    ASSERT_TRUE(got->T_world_cam.valid());
    ASSERT_TRUE(got->T_world_cam.t.allFinite());
    for (double d : got->p_c.distortion) ASSERT_TRUE(std::isfinite(d));
  }
  EXPECT_GT(accepted, 10'000u);
  EXPECT_GT(refused, 10'000u);
}

}  // namespace
}  // namespace hd::drivers
