#pragma once
// A head tracker on HID: any HidTransport, any HidReportFormat. Its thread reads reports,
// validates them (bad ones counted by reason and skipped, never published), stamps them on the
// monotonic clock and publishes to the mailbox (newest) and the ring (all).

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "drivers/camera_source.h"  // DeviceError
#include "drivers/clock/device_clock_mapper.h"
#include "drivers/hid/hid_report_format.h"
#include "drivers/hid/hid_report_parser.h"
#include "drivers/hid/hid_transport.h"
#include "drivers/pose_source.h"

namespace hd::drivers {

struct HidHeadTrackerConfig {
  std::string id = "hid-head-tracker";
  HidReportFormat format = android_head_tracker_v1();
  HidTransportOpener opener{};
  int64_t stall_timeout_ns = 250'000'000;    ///< no valid report for this long: kStalled
  int64_t reopen_interval_ns = 250'000'000;  ///< retry period while disconnected
  int read_timeout_ms = 20;                  ///< bounds how late stop() and stall detection are
  int report_interval_ms = 10;               ///< requested in the control feature report
  DeviceClockMapperConfig clock{};           ///< used when the format carries a device time
};

class HidHeadTracker : public PoseSource {
 public:
  explicit HidHeadTracker(HidHeadTrackerConfig config);
  ~HidHeadTracker() override;
  HidHeadTracker(const HidHeadTracker&) = delete;
  HidHeadTracker& operator=(const HidHeadTracker&) = delete;

  std::string id() const override { return config_.id; }
  /// Opens the device, checks its description feature report and starts its report stream.
  /// Throws DeviceError naming the device and what was expected.
  void open() override;
  void start() override;
  void stop() override;
  SourceState state() const override { return state_.load(std::memory_order_acquire); }
  uint64_t rejected_reports() const override { return rejected_.total(); }
  uint64_t rejected_reports(HidRejectReason reason) const { return rejected_.get(reason); }
  uint64_t reconnects() const { return reconnects_.load(std::memory_order_relaxed); }
  Mailbox<PoseSample>& latest() override { return latest_; }
  SpscRing<PoseSample, 1024>& history() override { return history_; }
  /// The last open/read failure, for `hybrid-station devices` and logs.
  std::string last_error() const;

 private:
  // Opens and performs the handshake; on failure returns nullptr and sets `why`.
  std::unique_ptr<HidTransport> open_and_start(std::string& why);
  void run();
  void handle_report(std::span<const uint8_t> report, int64_t arrival_ns);
  void set_error(std::string why);

  HidHeadTrackerConfig config_;
  std::unique_ptr<HidTransport> transport_;  // owned by the read thread while it runs
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<SourceState> state_{SourceState::kClosed};
  HidRejectCounters rejected_;
  std::atomic<uint64_t> reconnects_{0};
  Mailbox<PoseSample> latest_;
  SpscRing<PoseSample, 1024> history_;
  mutable std::mutex error_mutex_;
  std::string last_error_;

  // Read-thread state.
  DeviceClockMapper mapper_;
  int64_t last_good_ns_ = 0;
  uint64_t sequence_ = 0;
  uint32_t reset_counter_ = 0;
  bool have_discontinuity_ = false;
  uint8_t last_discontinuity_ = 0;
};

}  // namespace hd::drivers
