#include "drivers/hid/fake_hid_transport.h"

#include <algorithm>
#include <chrono>

namespace hd::drivers {

void FakeHidDevice::push_report(std::vector<uint8_t> bytes) {
  {
    std::lock_guard lock(mutex_);
    reports_.push_back(std::move(bytes));
  }
  cv_.notify_all();
}

void FakeHidDevice::unplug() {
  {
    std::lock_guard lock(mutex_);
    present_ = false;
    ++generation_;
    reports_.clear();
  }
  cv_.notify_all();
}

void FakeHidDevice::plug_in() {
  std::lock_guard lock(mutex_);
  present_ = true;
}

void FakeHidDevice::set_feature(uint8_t id, std::vector<uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  features_[id] = std::move(bytes);
}

std::vector<std::vector<uint8_t>> FakeHidDevice::sent_features() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

int FakeHidDevice::opens() const {
  std::lock_guard lock(mutex_);
  return opens_;
}

std::size_t FakeHidDevice::pending_reports() const {
  std::lock_guard lock(mutex_);
  return reports_.size();
}

HidTransportOpener FakeHidDevice::opener() {
  std::shared_ptr<FakeHidDevice> self = shared_from_this();
  return [self](std::string& why) -> std::unique_ptr<HidTransport> {
    std::lock_guard lock(self->mutex_);
    if (!self->present_) {
      why = "fake HID device unplugged";
      return nullptr;
    }
    ++self->opens_;
    return std::make_unique<FakeHidTransport>(self, self->generation_);
  };
}

int FakeHidTransport::read_report(std::span<uint8_t> buffer, int timeout_ms) {
  std::unique_lock lock(device_->mutex_);
  const auto ready = [&] {
    return device_->generation_ != generation_ || !device_->reports_.empty();
  };
  device_->cv_.wait_for(lock, std::chrono::milliseconds(std::max(timeout_ms, 0)), ready);
  if (device_->generation_ != generation_) {
    error_ = "fake HID device: read error (unplugged)";
    return -1;
  }
  if (device_->reports_.empty()) return 0;
  std::vector<uint8_t> r = std::move(device_->reports_.front());
  device_->reports_.pop_front();
  // Like hidraw: a report longer than the buffer is truncated to it.
  const std::size_t n = std::min(r.size(), buffer.size());
  std::copy_n(r.begin(), n, buffer.begin());
  return static_cast<int>(n);
}

int FakeHidTransport::get_feature_report(std::span<uint8_t> buffer) {
  std::lock_guard lock(device_->mutex_);
  if (device_->generation_ != generation_ || buffer.empty()) return -1;
  auto it = device_->features_.find(buffer[0]);
  if (it == device_->features_.end()) {
    error_ = "fake HID device: no such feature report";
    return -1;
  }
  const std::size_t n = std::min(it->second.size(), buffer.size());
  std::copy_n(it->second.begin(), n, buffer.begin());
  return static_cast<int>(n);
}

int FakeHidTransport::send_feature_report(std::span<const uint8_t> report) {
  std::lock_guard lock(device_->mutex_);
  if (device_->generation_ != generation_) return -1;
  device_->sent_.emplace_back(report.begin(), report.end());
  return static_cast<int>(report.size());
}

}  // namespace hd::drivers
