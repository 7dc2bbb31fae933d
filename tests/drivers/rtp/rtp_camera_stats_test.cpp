// RtpCameraCounters::snapshot: each counter lands in its RtpCameraStats field, totals are sums,
// and the SRTP figures follow from what was accepted and decrypted.
#include "drivers/rtp/rtp_camera_stats.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

TEST(RtpCameraCounters, ASnapshotCarriesEachCountAndTheMalformedTotal) {
  RtpCameraCounters c;
  RtpCameraStats s = c.snapshot(false);
  EXPECT_EQ(s.packets, 0u);
  EXPECT_EQ(s.last_camera_index, -1);  // none seen
  EXPECT_EQ(s.last_calibration_revision, -1);
  c.packets += 10;
  c.bytes += 12'000;
  c.accepted += 7;
  c.count(RtpPacketError::kTooShort);
  c.count(RtpPacketError::kTooShort);
  c.count(RtpPacketError::kBadVersion);
  c.count(StampError::kBadNtpSize);
  c.frames_published += 4;
  c.stamped += 3;
  c.unstamped += 1;
  c.not_newer += 2;
  c.capture_after_arrival += 1;
  c.key_frames += 1;
  c.last_key_frame_capture_ns = 123;
  c.last_camera_index = 2;
  c.last_calibration_revision = 9;
  c.sender_reports += 5;
  c.jitter_too_late += 6;
  c.jitter_over_latency += 7;
  c.packets_depayloaded += 8;
  c.frames_decoded += 11;
  c.frames_converted += 10;
  s = c.snapshot(false);
  EXPECT_EQ(s.packets, 10u);
  EXPECT_EQ(s.bytes, 12'000u);
  EXPECT_EQ(s.accepted, 7u);
  EXPECT_EQ(s.malformed[static_cast<std::size_t>(RtpPacketError::kTooShort)], 2u);
  EXPECT_EQ(s.malformed[static_cast<std::size_t>(RtpPacketError::kBadVersion)], 1u);
  EXPECT_EQ(s.malformed_total, 3u);
  EXPECT_EQ(s.packets, s.accepted + s.malformed_total);
  EXPECT_EQ(s.stamp_errors[static_cast<std::size_t>(StampError::kBadNtpSize)], 1u);
  EXPECT_EQ(s.frames_published, 4u);
  EXPECT_EQ(s.stamped_frames + s.unstamped_frames, s.frames_published);
  EXPECT_EQ(s.not_newer, 2u);
  EXPECT_EQ(s.capture_after_arrival, 1u);
  EXPECT_EQ(s.key_frames, 1u);
  EXPECT_EQ(s.last_key_frame_capture_ns, 123);
  EXPECT_EQ(s.last_camera_index, 2);
  EXPECT_EQ(s.last_calibration_revision, 9);
  EXPECT_EQ(s.sender_reports, 5u);
  EXPECT_EQ(s.jitter_too_late, 6u);
  EXPECT_EQ(s.jitter_over_latency, 7u);
  EXPECT_EQ(s.packets_depayloaded, 8u);
  EXPECT_EQ(s.frames_decoded, 11u);
  EXPECT_EQ(s.frames_converted, 10u);
  EXPECT_EQ(s.kernel_drops, -1);  // the sockets are the camera's: not in these counters
  c.decrypted += 5;
  EXPECT_EQ(c.snapshot(false).srtp_decrypted, 0u);  // no key: no SRTP figures
  EXPECT_EQ(c.snapshot(false).srtp_rejected, 0u);
}

TEST(RtpCameraCounters, WithAKeyWhatWasAcceptedButNotDecryptedIsRejected) {
  RtpCameraCounters c;
  c.accepted += 10;
  c.decrypted += 7;
  RtpCameraStats s = c.snapshot(true);
  EXPECT_EQ(s.srtp_decrypted, 7u);
  EXPECT_EQ(s.srtp_rejected, 3u);
  c.decrypted += 4;  // read between the two counters' updates: never negative
  s = c.snapshot(true);
  EXPECT_EQ(s.srtp_decrypted, 11u);
  EXPECT_EQ(s.srtp_rejected, 0u);
}

}  // namespace
}  // namespace hd::drivers
