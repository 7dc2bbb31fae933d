#include "drivers/hid/hid_head_tracker.h"

#include <array>
#include <chrono>
#include <cstring>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/hid/hid_report_encoder.h"

namespace hd::drivers {

HidHeadTracker::HidHeadTracker(HidHeadTrackerConfig config)
    : config_(std::move(config)), mapper_(config_.clock) {}

HidHeadTracker::~HidHeadTracker() {
  stop();
}

std::string HidHeadTracker::last_error() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

void HidHeadTracker::set_error(std::string why) {
  std::lock_guard lock(error_mutex_);
  last_error_ = std::move(why);
}

std::unique_ptr<HidTransport> HidHeadTracker::open_and_start(std::string& why) {
  if (!config_.opener) {
    why = "no transport configured";
    return nullptr;
  }
  std::unique_ptr<HidTransport> t = config_.opener(why);
  if (!t) return nullptr;
  const HidReportFormat& f = config_.format;
  if (!f.description.empty()) {
    std::array<uint8_t, 256> buf{};
    buf[0] = static_cast<uint8_t>(f.description_feature_id);
    const int n = t->get_feature_report(buf);
    const auto need = static_cast<int>(1 + f.description.size());
    if (n < need || std::memcmp(buf.data() + 1, f.description.data(), f.description.size()) != 0) {
      const int shown = n > 1 ? std::min<int>(n - 1, static_cast<int>(f.description.size())) : 0;
      why = "description feature report " + std::to_string(f.description_feature_id) + " is \"" +
            std::string(reinterpret_cast<const char*>(buf.data() + 1),
                        static_cast<std::size_t>(shown)) +
            "\" (" + std::to_string(n) + " bytes), expected \"" + f.description + "\": not a " +
            f.name + " device";
      return nullptr;
    }
  }
  if (f.control_feature_id >= 0) {
    std::array<uint8_t, 2> ctl{};
    const std::size_t len = encode_control_feature(f, true, config_.report_interval_ms, ctl);
    if (t->send_feature_report(std::span<const uint8_t>(ctl.data(), len)) < 0) {
      why = "writing the reporting-state feature report failed: " + t->error();
      return nullptr;
    }
  }
  return t;
}

void HidHeadTracker::open() {
  if (transport_ || running_) return;
  std::string why;
  transport_ = open_and_start(why);
  if (!transport_) {
    set_error(why);
    state_.store(SourceState::kDisconnected, std::memory_order_release);
    throw DeviceError("HID head tracker '" + config_.id + "' (" + config_.format.name +
                      "): " + why);
  }
  mapper_ = DeviceClockMapper(config_.clock);
  last_good_ns_ = monotonic_now_ns();
  state_.store(SourceState::kStreaming, std::memory_order_release);
}

void HidHeadTracker::start() {
  if (running_) return;
  if (!transport_) open();
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void HidHeadTracker::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
  if (transport_ && config_.format.control_feature_id >= 0) {
    std::array<uint8_t, 2> ctl{};
    const std::size_t len = encode_control_feature(config_.format, false, 0, ctl);
    transport_->send_feature_report(std::span<const uint8_t>(ctl.data(), len));  // best effort
  }
  transport_.reset();
  state_.store(SourceState::kClosed, std::memory_order_release);
}

void HidHeadTracker::handle_report(std::span<const uint8_t> report, int64_t arrival_ns) {
  const HidParseResult r = parse_hid_report(config_.format, report);
  if (!r.ok) {
    rejected_.count(r.reason);
    return;
  }
  const HidSample& s = r.sample;
  if (s.has_discontinuity) {
    if (have_discontinuity_ && s.discontinuity != last_discontinuity_) ++reset_counter_;
    have_discontinuity_ = true;
    last_discontinuity_ = s.discontinuity;
  }
  PoseSample& out = latest_.write_slot();
  out.T_tracker_head = core::Pose::from(s.q_tracker_head, Eigen::Vector3d::Zero());
  out.angular_velocity_rad_s = s.angular_velocity_rad_s;
  out.has_angular_velocity = s.has_angular_velocity;
  out.has_position = false;
  out.reset_counter = reset_counter_;
  out.sequence = sequence_++;
  if (s.has_timestamp) {
    out.host_timestamp_ns = mapper_.map(s.device_timestamp, arrival_ns);
    out.device_timestamp_ns = mapper_.last_device_ns();
    out.device_time_trusted = true;
  } else {
    out.host_timestamp_ns = arrival_ns;
    out.device_timestamp_ns = 0;
    out.device_time_trusted = false;
  }
  history_.push(out);
  latest_.publish();
  last_good_ns_ = arrival_ns;
  state_.store(SourceState::kStreaming, std::memory_order_release);
}

void HidHeadTracker::run() {
  std::array<uint8_t, 256> buf{};
  int64_t next_reopen_ns = 0;
  while (running_.load(std::memory_order_relaxed)) {
    if (!transport_) {
      const int64_t now = monotonic_now_ns();
      if (now < next_reopen_ns) {
        std::this_thread::sleep_for(std::chrono::milliseconds(config_.read_timeout_ms));
        continue;
      }
      std::string why;
      transport_ = open_and_start(why);
      if (!transport_) {
        set_error(why);
        next_reopen_ns = now + config_.reopen_interval_ns;
        continue;
      }
      // The device came back: its reference frame may differ from before.
      ++reconnects_;
      ++reset_counter_;
      have_discontinuity_ = false;
      mapper_ = DeviceClockMapper(config_.clock);
      last_good_ns_ = monotonic_now_ns();
      state_.store(SourceState::kStreaming, std::memory_order_release);
    }
    const int n = transport_->read_report(buf, config_.read_timeout_ms);
    const int64_t arrival_ns = monotonic_now_ns();
    if (n < 0) {
      set_error("read failed: " + transport_->error());
      transport_.reset();
      state_.store(SourceState::kDisconnected, std::memory_order_release);
      next_reopen_ns = arrival_ns;  // try at once: a replug is often immediate
      continue;
    }
    if (n > 0)
      handle_report(std::span<const uint8_t>(buf.data(), static_cast<std::size_t>(n)), arrival_ns);
    if (arrival_ns - last_good_ns_ > config_.stall_timeout_ns &&
        state_.load(std::memory_order_relaxed) == SourceState::kStreaming)
      state_.store(SourceState::kStalled, std::memory_order_release);
  }
}

}  // namespace hd::drivers
