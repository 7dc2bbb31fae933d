// A long randomized test of the HID parser (the fuzz requirement, runnable under ASan+UBSan with
// GCC): >= 10^6 random and mutated reports per run over both formats. Zero crashes, and every
// accepted report must give a finite unit quaternion and finite angular velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "drivers/hid/hid_report_encoder.h"
#include "drivers/hid/hid_report_format.h"
#include "drivers/hid/hid_report_parser.h"

namespace hd::drivers {
namespace {

struct Tally {
  uint64_t inputs = 0;
  uint64_t accepted = 0;
  uint64_t rejected[static_cast<int>(HidRejectReason::kCount)] = {};
};

void check(const HidReportFormat& f, const std::vector<uint8_t>& r, Tally& t) {
  ++t.inputs;
  const HidParseResult res = parse_hid_report(f, r);
  if (!res.ok) {
    ++t.rejected[static_cast<int>(res.reason)];
    return;
  }
  ++t.accepted;
  const auto& s = res.sample;
  ASSERT_TRUE(s.q_tracker_head.coeffs().allFinite());
  ASSERT_NEAR(s.q_tracker_head.norm(), 1.0, 1e-9);
  ASSERT_TRUE(s.angular_velocity_rad_s.allFinite());
  // Decoded angular velocity cannot exceed the format's full scale on any axis.
  ASSERT_LE(s.angular_velocity_rad_s.cwiseAbs().maxCoeff(),
            32768.0 * f.angular_velocity_field.lsb + 1e-9);
}

void write_i16(std::vector<uint8_t>& r, std::size_t at, int16_t v) {
  if (at + 1 >= r.size()) return;
  r[at] = static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF);
  r[at + 1] = static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8);
}

TEST(HidParserFuzz, MillionRandomAndMutatedReportsNeverCrashAndAcceptOnlySaneOutput) {
  std::mt19937_64 rng(0x5EED);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> coin(0, 99);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const HidReportFormat formats[] = {android_head_tracker_v1(), osvr_hdk()};
  Tally tally[2];
  constexpr int kPerFormat = 550'000;
  std::vector<uint8_t> r;
  for (int fi = 0; fi < 2; ++fi) {
    const HidReportFormat& f = formats[fi];
    for (int i = 0; i < kPerFormat; ++i) {
      const int kind = coin(rng);
      if (kind < 20) {
        // Pure random bytes of a random length around the real one.
        r.resize(static_cast<std::size_t>(std::uniform_int_distribution<int>(0, 48)(rng)));
        for (auto& b : r) b = static_cast<uint8_t>(byte(rng));
        if (!r.empty() && coin(rng) < 50 && f.report_id >= 0)
          r[0] = static_cast<uint8_t>(f.report_id);
      } else {
        // A valid report, then mutated.
        HidSample s;
        // Each draw its own statement: arguments are unsequenced, and GCC and clang differ.
        const double qz = gauss(rng), qy = gauss(rng), qx = gauss(rng), qw = gauss(rng);
        s.q_tracker_head = Eigen::Quaterniond(qw, qx, qy, qz);
        if (s.q_tracker_head.norm() < 1e-6) s.q_tracker_head = Eigen::Quaterniond::Identity();
        s.q_tracker_head.normalize();
        const double wz = gauss(rng), wy = gauss(rng), wx = gauss(rng);
        s.angular_velocity_rad_s = Eigen::Vector3d(wx, wy, wz) * 10.0;
        s.discontinuity = static_cast<uint8_t>(byte(rng));
        r.assign(64, 0);
        r.resize(encode_hid_report(f, s, r));
        const int m = coin(rng);
        if (m < 35) {
          const int flips = 1 + coin(rng) % 8;
          for (int k = 0; k < flips; ++k) {
            const auto bit = std::uniform_int_distribution<std::size_t>(0, r.size() * 8 - 1)(rng);
            r[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
          }
        } else if (m < 50) {
          r.resize(std::uniform_int_distribution<std::size_t>(0, r.size() - 1)(rng));
        } else if (m < 65) {
          const int extra = 1 + coin(rng) % 16;
          for (int k = 0; k < extra; ++k) r.push_back(static_cast<uint8_t>(byte(rng)));
        } else if (m < 85) {
          // -32768 injected into a random int16 slot.
          const auto at = std::uniform_int_distribution<std::size_t>(0, r.size() - 2)(rng);
          write_i16(r, at, INT16_MIN);
        }  // else: left valid
      }
      check(f, r, tally[fi]);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  for (int fi = 0; fi < 2; ++fi) {
    const Tally& t = tally[fi];
    std::printf("%s: %llu inputs, %llu accepted", formats[fi].name.c_str(),
                static_cast<unsigned long long>(t.inputs),
                static_cast<unsigned long long>(t.accepted));
    for (int k = 0; k < static_cast<int>(HidRejectReason::kCount); ++k)
      std::printf(", %s %llu", std::string(to_string(static_cast<HidRejectReason>(k))).c_str(),
                  static_cast<unsigned long long>(t.rejected[k]));
    std::printf("\n");
    // The mix must exercise both paths, or the test proves nothing.
    EXPECT_GT(t.accepted, 50'000u);
    EXPECT_GT(t.inputs - t.accepted, 50'000u);
  }
  EXPECT_GE(tally[0].inputs + tally[1].inputs, 1'000'000u);
  EXPECT_GT(tally[0].rejected[static_cast<int>(HidRejectReason::kForbiddenValue)], 1000u);
}

}  // namespace
}  // namespace hd::drivers
