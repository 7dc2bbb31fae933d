#pragma once
// A scripted HID device for tests: input reports, timeouts and failures are queued by the test;
// feature reports are served from a table and every written one is recorded. Unplugging makes
// the open transport fail and the opener refuse until the device is "plugged" back in.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "drivers/hid/hid_transport.h"

namespace hd::drivers {

class FakeHidDevice : public std::enable_shared_from_this<FakeHidDevice> {
 public:
  void push_report(std::vector<uint8_t> bytes);
  /// The next read fails (-1) and the device stays away until plug_in().
  void unplug();
  void plug_in();
  void set_feature(uint8_t id, std::vector<uint8_t> bytes);  ///< bytes include the id
  std::vector<std::vector<uint8_t>> sent_features() const;
  int opens() const;
  std::size_t pending_reports() const;

  /// An opener for HidHeadTracker bound to this device.
  HidTransportOpener opener();

 private:
  friend class FakeHidTransport;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::vector<uint8_t>> reports_;
  std::map<uint8_t, std::vector<uint8_t>> features_;
  std::vector<std::vector<uint8_t>> sent_;
  bool present_ = true;
  uint64_t generation_ = 0;  // bumps on unplug: transports of an older generation are dead
  int opens_ = 0;
};

class FakeHidTransport : public HidTransport {
 public:
  FakeHidTransport(std::shared_ptr<FakeHidDevice> device, uint64_t generation)
      : device_(std::move(device)), generation_(generation) {}
  int read_report(std::span<uint8_t> buffer, int timeout_ms) override;
  int get_feature_report(std::span<uint8_t> buffer) override;
  int send_feature_report(std::span<const uint8_t> report) override;
  std::string error() const override { return error_; }

 private:
  std::shared_ptr<FakeHidDevice> device_;
  uint64_t generation_;
  std::string error_;
};

}  // namespace hd::drivers
