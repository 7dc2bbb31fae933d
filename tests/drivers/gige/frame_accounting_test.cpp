// FrameAccounting: which counter each GigE buffer lands in, and the consumer's sequence across
// restarts and reconnects.
#include "drivers/gige/frame_accounting.h"

#include <arv.h>
#include <gtest/gtest.h>

#include <optional>

namespace hd::drivers {
namespace {

// Aravis gave up waiting for the frame's missing packets (GigeStats::last_bad_status's value).
constexpr int kTimeout = static_cast<int>(ARV_BUFFER_STATUS_TIMEOUT);

// Admits `frame_id` and, when it is the next one, publishes it: the consumer's sequence.
std::optional<uint64_t> publish(FrameAccounting& a, uint64_t frame_id) {
  const auto camera_sequence = a.admit(frame_id);
  if (!camera_sequence) return std::nullopt;
  const uint64_t s = a.sequence_for(*camera_sequence);
  a.published();
  return s;
}

TEST(FrameAccounting, FirstStartKeepsTheCamerasOwnIds) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  EXPECT_EQ(publish(a, 7), 7u);
  EXPECT_EQ(publish(a, 8), 8u);
  EXPECT_EQ(a.last_sequence(), 8u);
  EXPECT_EQ(c.snapshot().frames_published, 2u);
  EXPECT_EQ(c.dropped(), 0u);
}

TEST(FrameAccounting, SkippedIdsAreGapsAndDropped) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 5);
  EXPECT_EQ(publish(a, 9), 9u);  // 6, 7 and 8 never arrived
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.id_gaps, 3u);
  EXPECT_EQ(s.bad_buffers, 0u);
  EXPECT_EQ(c.dropped(), 3u);
}

TEST(FrameAccounting, ALostFrameIsCountedOnceNotAlsoAsAGap) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 10);
  a.lost(11, kTimeout);
  EXPECT_EQ(publish(a, 12), 12u);
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.bad_buffers, 1u);
  EXPECT_EQ(s.id_gaps, 0u);
  EXPECT_EQ(s.last_bad_status, kTimeout);
  EXPECT_EQ(s.bad_before_first_frame, 0u);  // a frame was published before it
  EXPECT_EQ(c.dropped(), 1u);
}

TEST(FrameAccounting, IdsSkippedBeforeALostOrWrongFormatFrameAreGapsToo) {
  // On a loaded machine the kernel can drop all of one frame's datagrams and part of the next's:
  // the first is missing from the ids, the second a bad buffer.
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 10);
  a.lost(12, kTimeout);  // 11 never arrived
  a.wrong_format(15);    // 13 and 14 never arrived
  EXPECT_EQ(publish(a, 16), 16u);
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.id_gaps, 3u);
  EXPECT_EQ(s.bad_buffers, 1u);
  EXPECT_EQ(s.wrong_format, 1u);
  EXPECT_EQ(c.dropped(), 4u);  // bad buffers and gaps (a wrong-format frame is counted apart)
}

TEST(FrameAccounting, LossesBeforeTheFirstFrameOfEachStartAreCountedApart) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  a.lost(1, kTimeout);
  a.lost(2, kTimeout);
  publish(a, 4);  // id 3 never came: a gap before the first frame
  a.lost(5, kTimeout);
  publish(a, 7);  // id 6: a gap after it
  a.reconnected();
  a.lost(1, kTimeout);  // the reopened camera's first frame, lost too
  publish(a, 3);        // id 2: before this start's first frame again
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.bad_buffers, 4u);
  EXPECT_EQ(s.bad_before_first_frame, 3u);
  EXPECT_EQ(s.id_gaps, 3u);
  EXPECT_EQ(s.gaps_before_first_frame, 2u);
}

TEST(FrameAccounting, LateDuplicateAndInvalidIdsAreSkippedAndCounted) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 20);
  EXPECT_EQ(publish(a, 20), std::nullopt);  // duplicate
  EXPECT_EQ(publish(a, 19), std::nullopt);  // late
  EXPECT_EQ(publish(a, 0), std::nullopt);   // 0 is no 16-bit GVSP id
  EXPECT_EQ(publish(a, 21), 21u);
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.late_or_duplicate, 2u);
  EXPECT_EQ(s.malformed, 1u);
  EXPECT_EQ(s.frames_published, 2u);
  EXPECT_EQ(c.dropped(), 0u);
}

TEST(FrameAccounting, WrongFormatFramesConsumeTheirIds) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 30);
  a.wrong_format(31);
  a.wrong_format(32);
  EXPECT_EQ(publish(a, 33), 33u);
  const GigeStats s = c.snapshot();
  EXPECT_EQ(s.wrong_format, 2u);
  EXPECT_EQ(s.id_gaps, 0u);
  EXPECT_EQ(c.dropped(), 0u);
}

TEST(FrameAccounting, AReconnectedCamerasRestartedIdsContinueTheSequence) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 41);
  publish(a, 42);
  a.reconnected();
  EXPECT_EQ(publish(a, 1), 43u);  // its ids started over at 1
  EXPECT_EQ(publish(a, 2), 44u);
  EXPECT_EQ(publish(a, 5), 47u);  // a gap after the reconnect is still a gap
  EXPECT_EQ(c.snapshot().id_gaps, 2u);
}

TEST(FrameAccounting, StopAndStartNeverMovesTheSequenceBackwards) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 100);
  a.start();                        // stop() and start(): our unwrapper starts over
  EXPECT_EQ(publish(a, 90), 101u);  // the camera's counter went on (or back): we follow ours
  EXPECT_EQ(publish(a, 91), 102u);
}

TEST(FrameAccounting, AStartBeforeAnyFrameKeepsTheCamerasIds) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  a.lost(3, kTimeout);
  a.start();  // nothing was published: nothing to continue
  EXPECT_EQ(publish(a, 500), 500u);
}

TEST(FrameAccounting, TheSequenceContinuesAcrossThe16BitWrap) {
  GigeCounters c;
  FrameAccounting a(c);
  a.start();
  publish(a, 65534);
  publish(a, 65535);
  EXPECT_EQ(publish(a, 1), 65536u);  // 65535 -> 1, 0 is skipped: no gap
  EXPECT_EQ(c.dropped(), 0u);
}

}  // namespace
}  // namespace hd::drivers
