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
  version[12] = 3;
  EXPECT_EQ(parse_view_feedback(version, f), ViewFeedbackError::kBadVersion);
  version[12] = 2;  // the authenticated version is 32 bytes long
  EXPECT_EQ(parse_view_feedback(version, f), ViewFeedbackError::kBadLength);
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

SrtpKey test_key(uint8_t first) {
  SrtpKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = uint8_t(first + i);
  return k;
}

TEST(ViewFeedback, TheAuthenticatedMessageCarriesTheTagPythonsHmacGives) {
  // Expected bytes from Python's hmac module, not from this code:
  //   k = hmac.new(bytes(range(1, 29)), b"hybrid-display view feedback", sha256).digest()
  //   hmac.new(k, the first 16 bytes below, sha256).digest()[:16]
  const ViewFeedbackKey key = view_feedback_key(test_key(1));
  std::array<uint8_t, kAuthenticatedViewFeedbackSize> b{};
  write_view_feedback({0x01020304u, false, 0xABCD}, key, b);
  const std::array<uint8_t, 32> expected = {0x80, 204,  0,    7,    1,    2,    3,    4,
                                            'H',  'D',  'B',  'W',  2,    0,    0xAB, 0xCD,
                                            0xde, 0x82, 0x80, 0x6f, 0xb1, 0x11, 0xaf, 0x10,
                                            0xc7, 0xf1, 0x25, 0x1b, 0x9a, 0x91, 0xa6, 0xb3};
  EXPECT_EQ(b, expected);
  ViewFeedback f;
  ASSERT_EQ(parse_view_feedback(b, &key, f), ViewFeedbackError::kNone);
  EXPECT_EQ(f.ssrc, 0x01020304u);
  EXPECT_FALSE(f.needed);
  EXPECT_EQ(f.sequence, 0xABCD);
}

TEST(ViewFeedback, WithAKeyOnlyMessagesTaggedWithThatKeyAreTaken) {
  const ViewFeedbackKey key = view_feedback_key(test_key(1));
  const ViewFeedbackKey other = view_feedback_key(test_key(2));
  ViewFeedback f;
  std::array<uint8_t, kViewFeedbackSize> plain{};
  write_view_feedback({0, false, 3}, plain);
  EXPECT_EQ(parse_view_feedback(plain, &key, f), ViewFeedbackError::kNotAuthenticated);
  std::array<uint8_t, kAuthenticatedViewFeedbackSize> tagged{};
  write_view_feedback({0, false, 3}, other, tagged);
  EXPECT_EQ(parse_view_feedback(tagged, &key, f), ViewFeedbackError::kBadTag);
  write_view_feedback({0, false, 3}, key, tagged);
  EXPECT_EQ(parse_view_feedback(tagged, f), ViewFeedbackError::kBadVersion) << "no key here";
  ASSERT_EQ(parse_view_feedback(tagged, &key, f), ViewFeedbackError::kNone);
  // Every single flipped bit, in the fields or in the tag, is refused.
  for (std::size_t bit = 0; bit < tagged.size() * 8; ++bit) {
    std::array<uint8_t, kAuthenticatedViewFeedbackSize> m = tagged;
    m[bit / 8] ^= uint8_t(1 << (bit % 8));
    EXPECT_NE(parse_view_feedback(m, &key, f), ViewFeedbackError::kNone) << "bit " << bit;
  }
}

}  // namespace
}  // namespace hd::drivers
