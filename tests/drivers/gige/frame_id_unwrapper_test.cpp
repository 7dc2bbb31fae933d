// GigE block ids (16-bit, 65535 -> 1, 0 reserved; or 64-bit extended) unwrapped to a sequence.
#include "drivers/gige/frame_id_unwrapper.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <vector>

namespace hd::drivers {
namespace {

using Verdict = FrameIdUnwrapper::Verdict;

TEST(FrameIdUnwrapper, WrapsFrom65535To1WithoutAGap) {
  FrameIdUnwrapper u;
  std::vector<uint64_t> seq;
  for (uint64_t id : {65533u, 65534u, 65535u, 1u, 2u, 3u}) {
    const auto r = u.update(id);
    ASSERT_EQ(r.verdict, Verdict::kNext) << id;
    EXPECT_EQ(r.gap, 0u) << id;
    seq.push_back(r.sequence);
  }
  EXPECT_EQ(seq, (std::vector<uint64_t>{65533, 65534, 65535, 65536, 65537, 65538}));
  EXPECT_EQ(u.dropped(), 0u);
}

TEST(FrameIdUnwrapper, CountsFramesLostAcrossTheWrap) {
  FrameIdUnwrapper u;
  u.update(65534);
  const auto r = u.update(2);  // 65535 and 1 never arrived (0 is not an id, so it is not lost)
  ASSERT_EQ(r.verdict, Verdict::kNext);
  EXPECT_EQ(r.gap, 2u);
  EXPECT_EQ(r.sequence, 65534u + 3u);
  EXPECT_EQ(u.dropped(), 2u);
}

TEST(FrameIdUnwrapper, RejectsZeroDuplicatesAndLateIds) {
  FrameIdUnwrapper u;
  EXPECT_EQ(u.update(0).verdict, Verdict::kInvalid);
  EXPECT_EQ(u.update(100).sequence, 100u);
  EXPECT_EQ(u.update(100).verdict, Verdict::kDuplicateOrLate);
  EXPECT_EQ(u.update(99).verdict, Verdict::kDuplicateOrLate);
  EXPECT_EQ(u.update(0).verdict, Verdict::kInvalid);
  const auto r = u.update(101);
  EXPECT_EQ(r.verdict, Verdict::kNext);
  EXPECT_EQ(r.sequence, 101u);
  EXPECT_EQ(u.late(), 2u);
  EXPECT_EQ(u.dropped(), 0u);
}

TEST(FrameIdUnwrapper, LateIdJustBeforeTheWrapIsNotANewCycle) {
  FrameIdUnwrapper u;
  u.update(65535);
  u.update(1);
  EXPECT_EQ(u.update(65535).verdict, Verdict::kDuplicateOrLate);  // a resend of the old frame
  EXPECT_EQ(u.update(2).sequence, 65537u);
}

TEST(FrameIdUnwrapper, ExtendedIdsNeverWrap) {
  FrameIdUnwrapper u;
  EXPECT_EQ(u.update(70000).sequence, 70000u);
  EXPECT_EQ(u.update(70001).gap, 0u);
  const auto r = u.update(70005);
  EXPECT_EQ(r.gap, 3u);
  EXPECT_EQ(u.update(65535).verdict, Verdict::kDuplicateOrLate);
  EXPECT_EQ(u.update(0).verdict, Verdict::kDuplicateOrLate);  // 0 is a valid but old extended id
}

// Any forward walk with steps of 1..1000 ids, seen through the 16-bit id, is recovered exactly.
RC_GTEST_PROP(FrameIdUnwrapperProperty, RecoversTheTrueCountFromSixteenBitIds, ()) {
  const uint64_t start = *rc::gen::inRange<uint64_t>(1, 200000);
  const auto steps =
      *rc::gen::container<std::vector<uint64_t>>(rc::gen::inRange<uint64_t>(1, 1000));
  const auto id16 = [](uint64_t n) { return (n - 1) % 65535 + 1; };
  FrameIdUnwrapper u;
  const auto first = u.update(id16(start));
  RC_ASSERT(first.verdict == Verdict::kNext);
  const uint64_t base = first.sequence;
  uint64_t n = start, lost = 0;
  for (uint64_t s : steps) {
    n += s;
    lost += s - 1;
    const auto r = u.update(id16(n));
    RC_ASSERT(r.verdict == Verdict::kNext);
    RC_ASSERT(r.gap == s - 1);
    RC_ASSERT(r.sequence - base == n - start);
  }
  RC_ASSERT(u.dropped() == lost);
}

}  // namespace
}  // namespace hd::drivers
