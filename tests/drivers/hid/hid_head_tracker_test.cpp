// HidHeadTracker end to end through the scripted FakeHidDevice: handshake bytes, publication,
// rejection by reason, discontinuity -> reset_counter, stall, unplug and reopen.
#include "drivers/hid/hid_head_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "drivers/hid/fake_hid_transport.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes android(int16_t rx, int16_t ry, int16_t rz, int16_t wx, uint8_t disc) {
  Bytes b{3};
  for (int16_t v : {rx, ry, rz, wx, int16_t{0}, int16_t{0}}) {
    b.push_back(static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF));
    b.push_back(static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8));
  }
  b.push_back(disc);
  return b;
}

std::shared_ptr<FakeHidDevice> android_device() {
  auto dev = std::make_shared<FakeHidDevice>();
  Bytes desc{1};
  for (char c : std::string("#AndroidHeadTracker#1.0")) desc.push_back(static_cast<uint8_t>(c));
  desc.resize(1 + 23 + 16, 0);  // + persistent unique id (all zero: standalone tracker)
  dev->set_feature(1, desc);
  return dev;
}

HidHeadTrackerConfig config_for(const std::shared_ptr<FakeHidDevice>& dev) {
  HidHeadTrackerConfig c;
  c.id = "fake-android";
  c.opener = dev->opener();
  c.stall_timeout_ns = 60'000'000;
  c.reopen_interval_ns = 10'000'000;
  c.read_timeout_ms = 5;
  return c;
}

TEST(HidHeadTracker, OpenChecksDescriptionAndWritesReportingStateFeature) {
  auto dev = android_device();
  HidHeadTracker t(config_for(dev));
  t.open();
  const auto sent = dev->sent_features();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0], (Bytes{2, 0x01 | 0x02 | (10 << 2)}));
  EXPECT_EQ(t.state(), SourceState::kStreaming);
  t.stop();
  // Stopping switches reporting off again.
  ASSERT_EQ(dev->sent_features().size(), 2u);
  EXPECT_EQ(dev->sent_features()[1], (Bytes{2, 0}));
  EXPECT_EQ(t.state(), SourceState::kClosed);
}

TEST(HidHeadTracker, WrongDescriptionRefusesToOpenAndSaysWhatWasExpected) {
  auto dev = std::make_shared<FakeHidDevice>();
  dev->set_feature(1, Bytes{1, 'K', 'B', 'D'});
  HidHeadTracker t(config_for(dev));
  try {
    t.open();
    FAIL() << "opened a device without the head tracker description";
  } catch (const DeviceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("fake-android"), std::string::npos) << msg;
    EXPECT_NE(msg.find("#AndroidHeadTracker#1.0"), std::string::npos) << msg;
    EXPECT_NE(msg.find("\"KBD\""), std::string::npos) << msg;
  }
  EXPECT_TRUE(dev->sent_features().empty());
}

TEST(HidHeadTracker, PublishesValidReportsSkipsBadOnesAndCountsThemByReason) {
  auto dev = android_device();
  HidHeadTracker t(config_for(dev));
  t.start();
  dev->push_report(android(0, 0, 0, 0, 0));
  dev->push_report(Bytes{3, 1, 2});                  // short
  dev->push_report(android(INT16_MIN, 0, 0, 0, 0));  // forbidden value
  dev->push_report(android(1000, 0, 0, 0, 0));
  Bytes wrong_id = android(0, 0, 0, 0, 0);
  wrong_id[0] = 7;
  dev->push_report(wrong_id);
  dev->push_report(android(32767, 32767, 32767, 0, 0));  // |v| > pi
  dev->push_report(android(0, 0, 32767, 32767, 0));      // last valid: pi about Z, 32 rad/s
  ASSERT_TRUE(eventually([&] { return t.latest().published() == 3; }));
  ASSERT_TRUE(eventually([&] { return dev->pending_reports() == 0; }));

  EXPECT_EQ(t.rejected_reports(), 4u);
  EXPECT_EQ(t.rejected_reports(HidRejectReason::kWrongLength), 1u);
  EXPECT_EQ(t.rejected_reports(HidRejectReason::kForbiddenValue), 1u);
  EXPECT_EQ(t.rejected_reports(HidRejectReason::kWrongReportId), 1u);
  EXPECT_EQ(t.rejected_reports(HidRejectReason::kOutOfRange), 1u);

  // The ring has every valid sample in order; the mailbox the newest.
  std::vector<PoseSample> all;
  PoseSample s;
  while (t.history().pop(s)) all.push_back(s);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].sequence, 0u);
  EXPECT_EQ(all[2].sequence, 2u);
  EXPECT_LE(all[0].host_timestamp_ns, all[1].host_timestamp_ns);
  // Sample 1: 1000 counts about device X = station x.
  const double a1 = std::numbers::pi * 1000.0 / 32767.0;
  const Eigen::Matrix3d R0 = all[0].T_tracker_head.R;
  const Eigen::Matrix3d delta = R0.transpose() * all[1].T_tracker_head.R;  // head-frame motion
  EXPECT_NEAR(Eigen::AngleAxisd(delta).angle(), a1, 1e-9);
  EXPECT_TRUE(Eigen::AngleAxisd(delta).axis().isApprox(Eigen::Vector3d::UnitX(), 1e-9));

  ASSERT_TRUE(t.latest().fetch());
  const PoseSample& newest = t.latest().latest();
  EXPECT_EQ(newest.sequence, 2u);
  EXPECT_FALSE(newest.has_position);
  EXPECT_FALSE(newest.device_time_trusted);  // the Android report has no device time
  EXPECT_NEAR(newest.angular_velocity_rad_s.x(), 32.0, 1e-12);
  t.stop();
}

TEST(HidHeadTracker, DiscontinuityCounterChangeBumpsResetCounter) {
  auto dev = android_device();
  HidHeadTracker t(config_for(dev));
  t.start();
  for (uint8_t d : {9, 9, 10, 10, 0}) dev->push_report(android(0, 0, 0, 0, d));
  ASSERT_TRUE(eventually([&] { return t.latest().published() == 5; }));
  std::vector<uint32_t> resets;
  PoseSample s;
  while (t.history().pop(s)) resets.push_back(s.reset_counter);
  EXPECT_EQ(resets, (std::vector<uint32_t>{0, 0, 1, 1, 2}));
  t.stop();
}

TEST(HidHeadTracker, SilenceBecomesStalledAndDataResumesStreaming) {
  auto dev = android_device();
  HidHeadTracker t(config_for(dev));
  t.start();
  ASSERT_TRUE(eventually([&] { return t.state() == SourceState::kStalled; }));
  // Garbage is not data: it must not clear the stall.
  dev->push_report(Bytes{3, 0});
  ASSERT_TRUE(eventually([&] { return t.rejected_reports() == 1; }));
  EXPECT_EQ(t.state(), SourceState::kStalled);
  dev->push_report(android(0, 0, 0, 0, 0));
  ASSERT_TRUE(eventually([&] { return t.state() == SourceState::kStreaming; }));
  t.stop();
}

TEST(HidHeadTracker, UnplugIsDisconnectedAndReplugReopensAndStreams) {
  auto dev = android_device();
  HidHeadTracker t(config_for(dev));
  t.start();
  dev->push_report(android(0, 0, 0, 0, 4));
  ASSERT_TRUE(eventually([&] { return t.latest().published() == 1; }));
  dev->unplug();
  ASSERT_TRUE(eventually([&] { return t.state() == SourceState::kDisconnected; }));
  EXPECT_NE(t.last_error().find("unplugged"), std::string::npos) << t.last_error();
  EXPECT_EQ(dev->opens(), 1);

  dev->plug_in();
  ASSERT_TRUE(eventually([&] { return t.reconnects() == 1; }));
  // The reopened device got the handshake again.
  ASSERT_TRUE(eventually([&] { return dev->sent_features().size() == 2; }));
  EXPECT_EQ(dev->sent_features()[1][0], 2);
  dev->push_report(android(0, 0, 0, 0, 4));
  ASSERT_TRUE(eventually([&] { return t.latest().published() == 2; }));
  EXPECT_EQ(t.state(), SourceState::kStreaming);
  EXPECT_EQ(dev->opens(), 2);
  ASSERT_TRUE(t.latest().fetch());
  // A reconnect may change the reference frame: the reset counter says so.
  EXPECT_EQ(t.latest().latest().reset_counter, 1u);
  t.stop();
}

TEST(HidHeadTracker, OpenWithNoDeviceThrowsNamingIt) {
  auto dev = android_device();
  dev->unplug();
  HidHeadTracker t(config_for(dev));
  EXPECT_THROW(t.open(), DeviceError);
  EXPECT_EQ(t.state(), SourceState::kDisconnected);
}

TEST(HidHeadTracker, DeviceTimestampFormatIsMappedOntoHostClock) {
  auto dev = android_device();
  HidHeadTrackerConfig c = config_for(dev);
  c.format.input_length_bytes = 18;
  c.format.timestamp_offset_bytes = 14;
  c.format.timestamp_bytes = 4;
  c.clock = {.counter_bits = 32, .tick_ns = 1000.0};
  HidHeadTracker t(c);
  t.start();
  for (uint32_t us : {1'000'000u, 1'010'000u}) {
    Bytes r = android(0, 0, 0, 0, 0);
    for (int i = 0; i < 4; ++i) r.push_back(static_cast<uint8_t>(us >> (8 * i)));
    dev->push_report(r);
  }
  ASSERT_TRUE(eventually([&] { return t.latest().published() == 2; }));
  PoseSample a, b;
  ASSERT_TRUE(t.history().pop(a));
  ASSERT_TRUE(t.history().pop(b));
  EXPECT_TRUE(b.device_time_trusted);
  EXPECT_EQ(b.device_timestamp_ns - a.device_timestamp_ns, 10'000'000);
  EXPECT_GE(b.host_timestamp_ns, a.host_timestamp_ns);
  t.stop();
}

}  // namespace
}  // namespace hd::drivers
