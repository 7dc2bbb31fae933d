// The view feedback message (RTCP APP "HDBW"): written bytes against RFC 3550 section 6.7 by
// hand, read back, and every malformation refused by reason; ordinary RTCP is not taken.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "drivers/rtp/view_feedback.h"

namespace hd::drivers {
namespace {

TEST(ViewFeedback, TheWrittenBytesAreAnRfc3550AppPacketNamedHdbw) {
  std::array<uint8_t, kViewFeedbackSize> b{};
  write_view_feedback({0x01020304u, false, 0xABCD}, b);
  const std::array<uint8_t, 16> expected = {0x80, 204, 0,   3,   1, 2, 3,    4,
                                            'H',  'D', 'B', 'W', 1, 0, 0xAB, 0xCD};
  EXPECT_EQ(b, expected);
  ViewFeedback f;
  ASSERT_EQ(parse_view_feedback(b, f), ViewFeedbackError::kNone);
  EXPECT_EQ(f.ssrc, 0x01020304u);
  EXPECT_FALSE(f.needed);
  EXPECT_EQ(f.sequence, 0xABCD);
  write_view_feedback({0, true, 1}, b);
  ASSERT_EQ(parse_view_feedback(b, f), ViewFeedbackError::kNone);
  EXPECT_TRUE(f.needed);
}

TEST(ViewFeedback, OrdinaryRtcpIsNotTakenAndMalformedHdbwIsRefusedByReason) {
  // A receiver report (PT 201) header: RTCP for rtpbin, not ours.
  const std::vector<uint8_t> rr = {0x81, 201, 0, 7, 0, 0, 0, 1, 'H', 'D', 'B', 'W'};
  ViewFeedback f;
  EXPECT_EQ(parse_view_feedback(rr, f), ViewFeedbackError::kNotViewFeedback);
  EXPECT_EQ(parse_view_feedback(std::span<const uint8_t>(), f),
            ViewFeedbackError::kNotViewFeedback);
  std::array<uint8_t, kViewFeedbackSize> good{};
  write_view_feedback({0, true, 7}, good);
  std::vector<uint8_t> other_name(good.begin(), good.end());
  other_name[11] = 'X';
  EXPECT_EQ(parse_view_feedback(other_name, f), ViewFeedbackError::kNotViewFeedback);
  std::vector<uint8_t> longer(good.begin(), good.end());
  longer.push_back(0);
  EXPECT_EQ(parse_view_feedback(longer, f), ViewFeedbackError::kBadLength);
  std::vector<uint8_t> wrong_length(good.begin(), good.end());
  wrong_length[3] = 4;
  EXPECT_EQ(parse_view_feedback(wrong_length, f), ViewFeedbackError::kBadLength);
  std::vector<uint8_t> truncated(good.begin(), good.begin() + 13);
  EXPECT_EQ(parse_view_feedback(truncated, f), ViewFeedbackError::kBadLength);
  std::vector<uint8_t> version(good.begin(), good.end());
  version[12] = 2;
  EXPECT_EQ(parse_view_feedback(version, f), ViewFeedbackError::kBadVersion);
  std::vector<uint8_t> flags(good.begin(), good.end());
  flags[13] = 0x81;
  EXPECT_EQ(parse_view_feedback(flags, f), ViewFeedbackError::kBadVersion);
  std::vector<uint8_t> subtype(good.begin(), good.end());
  subtype[0] = 0x81;
  EXPECT_EQ(parse_view_feedback(subtype, f), ViewFeedbackError::kBadVersion);
}

TEST(ViewFeedback, MutatedMessagesNeverReadOutsideAndOnlyWellFormedOnesAreTaken) {
  std::mt19937 rng(12);
  std::array<uint8_t, kViewFeedbackSize> good{};
  write_view_feedback({5, true, 9}, good);
  uint64_t taken = 0;
  for (int i = 0; i < 200'000; ++i) {
    std::vector<uint8_t> m(good.begin(), good.end());
    m.resize(rng() % 24, uint8_t(rng()));
    for (int k = rng() % 3; k > 0 && !m.empty(); --k)
      m[rng() % m.size()] ^= uint8_t(1 << (rng() % 8));
    ViewFeedback f;
    if (parse_view_feedback(m, f) != ViewFeedbackError::kNone) continue;
    ++taken;
    // Taken only as exactly what write_view_feedback makes of the fields read.
    std::array<uint8_t, kViewFeedbackSize> again{};
    write_view_feedback(f, again);
    ASSERT_EQ(std::vector<uint8_t>(again.begin(), again.end()), m);
  }
  EXPECT_GT(taken, 0u);
}

}  // namespace
}  // namespace hd::drivers
