// ViewFeedbackSchedule with the time passed in: nothing before a need and a sender are known, a
// change at once, the same need every 0.5 s, a new sender at once; the messages it composes
// parse back (tagged with the stream's key when there is one).
#include "drivers/rtp/view_feedback_schedule.h"

#include <gtest/gtest.h>

#include <span>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;

ViewFeedback parsed(const ViewFeedbackSchedule::Message& m, const ViewFeedbackKey* key = nullptr) {
  ViewFeedback f;
  EXPECT_EQ(parse_view_feedback(std::span<const uint8_t>(m.bytes.data(), m.size), key, f),
            ViewFeedbackError::kNone);
  return f;
}

TEST(ViewFeedbackSchedule, NothingIsDueBeforeANeedAndASenderAreKnown) {
  ViewFeedbackSchedule s;
  EXPECT_TRUE(s.needed());  // full rate until told otherwise
  EXPECT_FALSE(s.due(1 * kMs));
  s.set_target("10.0.0.2", 5001);
  EXPECT_FALSE(s.due(2 * kMs));  // never set: the sender stays at full rate
  ViewFeedbackSchedule t;
  t.set_needed(false);
  EXPECT_FALSE(t.needed());
  EXPECT_FALSE(t.due(3 * kMs));  // no sender yet
  t.set_target("10.0.0.2", 5001);
  EXPECT_TRUE(t.due(3 * kMs));
}

TEST(ViewFeedbackSchedule, TheSameNeedGoesOutEveryHalfSecondAndAChangeAtOnce) {
  ViewFeedbackSchedule s;
  s.set_needed(false);
  s.set_target("10.0.0.2", 5001);
  const int64_t t0 = 1'000 * kMs;
  ASSERT_TRUE(s.due(t0));
  ViewFeedbackSchedule::Message m = s.take(t0);
  EXPECT_EQ(m.host, "10.0.0.2");
  EXPECT_EQ(m.port, 5001);
  EXPECT_EQ(m.size, kViewFeedbackSize);
  ViewFeedback f = parsed(m);
  EXPECT_FALSE(f.needed);
  EXPECT_EQ(f.sequence, 1);
  EXPECT_FALSE(s.due(t0));
  EXPECT_FALSE(s.due(t0 + ViewFeedbackSchedule::kRepeatNs - 1));
  EXPECT_TRUE(s.due(t0 + ViewFeedbackSchedule::kRepeatNs));
  m = s.take(t0 + ViewFeedbackSchedule::kRepeatNs);
  EXPECT_EQ(parsed(m).sequence, 2);
  EXPECT_FALSE(parsed(m).needed);
  s.set_needed(true);  // a change: at once, not at the next repeat
  EXPECT_TRUE(s.due(t0 + ViewFeedbackSchedule::kRepeatNs + 1));
  f = parsed(s.take(t0 + ViewFeedbackSchedule::kRepeatNs + 1));
  EXPECT_TRUE(f.needed);
  EXPECT_EQ(f.sequence, 3);
  s.set_needed(true);  // the same again: no change
  EXPECT_FALSE(s.due(t0 + ViewFeedbackSchedule::kRepeatNs + 2));
}

TEST(ViewFeedbackSchedule, ANewSenderHearsTheNeedAtOnce) {
  ViewFeedbackSchedule s;
  s.set_needed(true);
  s.set_target("10.0.0.2", 5001);
  s.take(10 * kMs);
  EXPECT_FALSE(s.due(11 * kMs));
  s.set_target("10.0.0.3", 6001);
  ASSERT_TRUE(s.due(11 * kMs));
  const ViewFeedbackSchedule::Message m = s.take(11 * kMs);
  EXPECT_EQ(m.host, "10.0.0.3");
  EXPECT_EQ(m.port, 6001);
}

TEST(ViewFeedbackSchedule, WithTheStreamsKeyEveryMessageCarriesItsTag) {
  SrtpKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = uint8_t(i * 7 + 1);
  const ViewFeedbackKey tag_key = view_feedback_key(key);
  ViewFeedbackSchedule s(tag_key);
  s.set_needed(false);
  s.set_target("10.0.0.2", 5001);
  const ViewFeedbackSchedule::Message m = s.take(1 * kMs);
  EXPECT_EQ(m.size, kAuthenticatedViewFeedbackSize);
  EXPECT_FALSE(parsed(m, &tag_key).needed);
  SrtpKey other = key;
  other.bytes[0] ^= 1;
  const ViewFeedbackKey other_tag = view_feedback_key(other);
  ViewFeedback f;
  EXPECT_EQ(parse_view_feedback(std::span<const uint8_t>(m.bytes.data(), m.size), &other_tag, f),
            ViewFeedbackError::kBadTag);
}

TEST(ViewFeedbackSchedule, OnlyMessagesThatWentOutAreCountedAsSent) {
  ViewFeedbackSchedule s;
  s.set_needed(true);
  s.set_target("10.0.0.2", 5001);
  s.take(1 * kMs);  // composed, but the socket refused it: not counted
  EXPECT_EQ(s.sent(), 0u);
  s.take(2 * kMs);
  s.count_sent();
  EXPECT_EQ(s.sent(), 1u);
}

}  // namespace
}  // namespace hd::drivers
