#pragma once
// A simulated Android head tracker behind the HidTransport seam: it answers the description
// feature report, streams only after the host has written the reporting-state feature report,
// and emits byte-exact input reports (via the real encoder, never -32768) from a scripted motion
// at the requested interval. The real parser and HidHeadTracker run unchanged on top of it.

#include <atomic>
#include <memory>

#include "drivers/hid/hid_report_format.h"
#include "drivers/hid/hid_transport.h"
#include "drivers/mock/mock_pose_source.h"

namespace hd::drivers {

/// Shared control over the simulated device (the test's or simulator's "hands").
struct MockHeadTrackerControl {
  std::atomic<bool> plugged_in{true};
  std::atomic<uint8_t> discontinuity{0};  ///< bump to signal a reference-frame jump
  std::atomic<uint64_t> reports_sent{0};
};

struct MockHeadTrackerConfig {
  HidReportFormat format = android_head_tracker_v1();
  ScriptedMotion motion{};  ///< head pose at t seconds since the device was opened
  std::shared_ptr<MockHeadTrackerControl> control = std::make_shared<MockHeadTrackerControl>();
};

class MockHeadTrackerTransport : public HidTransport {
 public:
  explicit MockHeadTrackerTransport(MockHeadTrackerConfig config);
  int read_report(std::span<uint8_t> buffer, int timeout_ms) override;
  int get_feature_report(std::span<uint8_t> buffer) override;
  int send_feature_report(std::span<const uint8_t> report) override;
  std::string error() const override { return "mock head tracker unplugged"; }

 private:
  MockHeadTrackerConfig config_;
  int64_t open_ns_;
  int64_t next_report_ns_ = 0;
  int64_t interval_ns_ = 0;  ///< 0: streaming off (the host has not asked yet)
};

/// An opener for HidHeadTracker: a fresh simulated device each time, refused while unplugged.
HidTransportOpener mock_head_tracker_opener(MockHeadTrackerConfig config);

}  // namespace hd::drivers
