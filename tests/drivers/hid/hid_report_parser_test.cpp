// The parser against hand-written byte-exact reports whose meaning follows in closed form from
// the protocols (Android head tracker 1.0, OSVR HDK), plus an encode -> parse round trip.
#include "drivers/hid/hid_report_parser.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "drivers/hid/hid_report_encoder.h"
#include "drivers/hid/hid_report_format.h"

namespace hd::drivers {
namespace {

using Bytes = std::vector<uint8_t>;
constexpr double kPi = std::numbers::pi;

// Station head axes in the Android head frame, written out by hand from the protocol text:
// station x (right) = device X, station y (down) = -device Z, station z (forward) = device Y.
Eigen::Matrix3d android_axes() {
  Eigen::Matrix3d A;
  A.col(0) = Eigen::Vector3d(1, 0, 0);
  A.col(1) = Eigen::Vector3d(0, 0, -1);
  A.col(2) = Eigen::Vector3d(0, 1, 0);
  return A;
}

Bytes android(int16_t rx, int16_t ry, int16_t rz, int16_t wx, int16_t wy, int16_t wz,
              uint8_t disc) {
  Bytes b{3};
  for (int16_t v : {rx, ry, rz, wx, wy, wz}) {
    b.push_back(static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF));
    b.push_back(static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8));
  }
  b.push_back(disc);
  return b;
}

TEST(HidReportParser, AndroidFullScaleRotationVectorIsPiAboutX) {
  const Bytes r = {0x03, 0xFF, 0x7F, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x05};
  const auto res = parse_hid_report(android_head_tracker_v1(), r);
  ASSERT_TRUE(res.ok) << to_string(res.reason);
  // pi about x: diag(1, -1, -1) in the device frame.
  const Eigen::Matrix3d R_tracker_device = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d expected = R_tracker_device * android_axes();
  EXPECT_TRUE(res.sample.q_tracker_head.toRotationMatrix().isApprox(expected, 1e-12))
      << res.sample.q_tracker_head.toRotationMatrix();
  EXPECT_TRUE(res.sample.has_discontinuity);
  EXPECT_EQ(res.sample.discontinuity, 5);
}

TEST(HidReportParser, AndroidRotationVectorAboutZIsYawByScaledAngle) {
  const auto res = parse_hid_report(android_head_tracker_v1(), android(0, 0, 16384, 0, 0, 0, 0));
  ASSERT_TRUE(res.ok);
  const double th = kPi * 16384.0 / 32767.0;
  Eigen::Matrix3d Rz;
  Rz << std::cos(th), -std::sin(th), 0, std::sin(th), std::cos(th), 0, 0, 0, 1;
  EXPECT_TRUE(res.sample.q_tracker_head.toRotationMatrix().isApprox(Rz * android_axes(), 1e-12));
}

TEST(HidReportParser, AndroidAngularVelocityScalesTo32RadPerSecondInStationAxes) {
  const auto res =
      parse_hid_report(android_head_tracker_v1(), android(0, 0, 0, 32767, -16384, 1000, 0));
  ASSERT_TRUE(res.ok);
  ASSERT_TRUE(res.sample.has_angular_velocity);
  const double k = 32.0 / 32767.0;
  // device (X, Y, Z) -> station (x = X, y = -Z, z = Y)
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.x(), 32.0, 1e-12);
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.y(), -1000 * k, 1e-12);
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.z(), -16384 * k, 1e-12);
}

TEST(HidReportParser, AndroidRejectsEachMalformationByReason) {
  const HidReportFormat f = android_head_tracker_v1();
  Bytes good = android(100, -200, 300, 1, 2, 3, 0);
  ASSERT_TRUE(parse_hid_report(f, good).ok);

  Bytes shorter(good.begin(), good.end() - 1);
  EXPECT_EQ(parse_hid_report(f, shorter).reason, HidRejectReason::kWrongLength);
  Bytes longer = good;
  longer.push_back(0);
  EXPECT_EQ(parse_hid_report(f, longer).reason, HidRejectReason::kWrongLength);
  EXPECT_EQ(parse_hid_report(f, Bytes{}).reason, HidRejectReason::kWrongLength);
  Bytes wrong_id = good;
  wrong_id[0] = 2;
  EXPECT_EQ(parse_hid_report(f, wrong_id).reason, HidRejectReason::kWrongReportId);
  EXPECT_EQ(parse_hid_report(f, android(100, INT16_MIN, 0, 0, 0, 0, 0)).reason,
            HidRejectReason::kForbiddenValue);
  EXPECT_EQ(parse_hid_report(f, android(0, 0, 0, 0, 0, INT16_MIN, 0)).reason,
            HidRejectReason::kForbiddenValue);
  // |v| = pi * sqrt(3): longer than the protocol's [0, pi].
  EXPECT_EQ(parse_hid_report(f, android(32767, 32767, 32767, 0, 0, 0, 0)).reason,
            HidRejectReason::kOutOfRange);
}

TEST(HidReportParser, FormatWithNonFiniteScaleIsRejectedNotPublished) {
  HidReportFormat f = android_head_tracker_v1();
  f.angular_velocity_field.lsb = std::numeric_limits<double>::infinity();
  EXPECT_EQ(parse_hid_report(f, android(0, 0, 0, 0, 0, 0, 0)).reason, HidRejectReason::kNonFinite);
  f = android_head_tracker_v1();
  f.orientation_field.lsb = std::nan("");
  EXPECT_EQ(parse_hid_report(f, android(1, 0, 0, 0, 0, 0, 0)).reason, HidRejectReason::kNonFinite);
}

Bytes osvr(int16_t x, int16_t y, int16_t z, int16_t w, int16_t gx, int16_t gy, int16_t gz) {
  Bytes b(32, 0);
  b[0] = 3;   // report version
  b[1] = 42;  // sequence
  int at = 2;
  for (int16_t v : {x, y, z, w, gx, gy, gz}) {
    b[static_cast<std::size_t>(at++)] = static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF);
    b[static_cast<std::size_t>(at++)] = static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8);
  }
  return b;
}

TEST(HidReportParser, OsvrIdentityQuaternionIsOsvrAxesFlipped) {
  const auto res = parse_hid_report(osvr_hdk(), osvr(0, 0, 0, 1 << 14, 0, 0, 0));
  ASSERT_TRUE(res.ok) << to_string(res.reason);
  // OSVR: x right, y up, z back; station: x right, y down, z forward.
  const Eigen::Matrix3d expected = Eigen::Vector3d(1, -1, -1).asDiagonal();
  EXPECT_TRUE(res.sample.q_tracker_head.toRotationMatrix().isApprox(expected, 1e-12));
  EXPECT_TRUE(res.sample.has_sequence);
  EXPECT_EQ(res.sample.sequence, 42);
  EXPECT_FALSE(res.sample.has_discontinuity);
}

TEST(HidReportParser, OsvrQuarterTurnAboutYAndGyroWithNineFractionalBits) {
  // 90 degrees about y: (x, y, z, w) = (0, sin 45, 0, cos 45) * 2^14, rounded.
  const int16_t h = 11585;
  const auto res = parse_hid_report(osvr_hdk(), osvr(0, h, 0, h, 512, 0, -1024));
  ASSERT_TRUE(res.ok);
  Eigen::Matrix3d Ry;
  Ry << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  const Eigen::Matrix3d expected = Ry * Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal());
  EXPECT_TRUE(res.sample.q_tracker_head.toRotationMatrix().isApprox(expected, 1e-4));
  // 512 / 2^9 = 1 rad/s; device (1, 0, -2) -> station (1, -0, 2).
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.x(), 1.0, 1e-12);
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.y(), 0.0, 1e-12);
  EXPECT_NEAR(res.sample.angular_velocity_rad_s.z(), 2.0, 1e-12);
}

TEST(HidReportParser, OsvrRejectsZeroAndOverlongQuaternions) {
  EXPECT_EQ(parse_hid_report(osvr_hdk(), osvr(0, 0, 0, 0, 0, 0, 0)).reason,
            HidRejectReason::kUnnormalisable);
  EXPECT_EQ(parse_hid_report(osvr_hdk(), osvr(INT16_MIN, 0, 0, 1 << 14, 0, 0, 0)).reason,
            HidRejectReason::kUnnormalisable);
  EXPECT_EQ(parse_hid_report(osvr_hdk(), Bytes(31, 0)).reason, HidRejectReason::kWrongLength);
}

TEST(HidReportParser, OptionalDeviceTimestampFieldIsReadLittleEndian) {
  HidReportFormat f = android_head_tracker_v1();
  f.input_length_bytes = 18;
  f.timestamp_offset_bytes = 14;
  f.timestamp_bytes = 4;
  Bytes r = android(0, 0, 0, 0, 0, 0, 0);
  for (uint8_t b : {0x78, 0x56, 0x34, 0x12}) r.push_back(b);
  const auto res = parse_hid_report(f, r);
  ASSERT_TRUE(res.ok);
  EXPECT_EQ(res.sample.device_timestamp, 0x12345678u);
}

TEST(HidReportEncoder, ControlFeatureStartsAllEventsFullPowerAtInterval) {
  uint8_t out[2];
  ASSERT_EQ(encode_control_feature(android_head_tracker_v1(), true, 10, out), 2u);
  EXPECT_EQ(out[0], 2);
  EXPECT_EQ(out[1], 0x01 | 0x02 | (10 << 2));
  ASSERT_EQ(encode_control_feature(android_head_tracker_v1(), false, 10, out), 2u);
  EXPECT_EQ(out[1], 0);
}

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

RC_GTEST_PROP(HidReportRoundTrip, EncodeThenParseRecoversPoseForBothFormats, ()) {
  const auto qc = *rc::gen::container<std::vector<int>>(4, rc::gen::inRange(-1000, 1001));
  Eigen::Quaterniond q(qc[0], qc[1], qc[2], qc[3]);
  RC_PRE(q.norm() > 10.0);
  q.normalize();
  const auto wc = *rc::gen::container<std::vector<int>>(3, rc::gen::inRange(-3000, 3001));
  HidSample s;
  s.q_tracker_head = q;
  s.angular_velocity_rad_s = Eigen::Vector3d(wc[0], wc[1], wc[2]) / 1000.0;  // within +-3 rad/s
  s.discontinuity = static_cast<uint8_t>(*rc::gen::inRange(0, 256));
  for (const HidReportFormat& f : {android_head_tracker_v1(), osvr_hdk()}) {
    uint8_t buf[64];
    const std::size_t n = encode_hid_report(f, s, buf);
    RC_ASSERT(n == static_cast<std::size_t>(f.input_length_bytes));
    const auto res = parse_hid_report(f, std::span<const uint8_t>(buf, n));
    RC_ASSERT(res.ok);
    // Quantisation: Android 3 components of pi/32767, OSVR 4 of 2^-14.
    RC_ASSERT(angle_between(res.sample.q_tracker_head, q) < 5e-4);
    RC_ASSERT((res.sample.angular_velocity_rad_s - s.angular_velocity_rad_s).norm() < 5e-3);
    if (f.discontinuity_offset_bytes >= 0) RC_ASSERT(res.sample.discontinuity == s.discontinuity);
  }
}

}  // namespace
}  // namespace hd::drivers
