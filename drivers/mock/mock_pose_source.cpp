#include "drivers/mock/mock_pose_source.h"

#include <chrono>
#include <cmath>

#include "drivers/camera_source.h"  // DeviceError
#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {

ScriptedMotion from_trajectory(Trajectory trajectory) {
  const double t0 = trajectory.samples().empty() ? 0.0 : trajectory.samples().front().t_s;
  return [traj = std::move(trajectory), t0](double t_s) { return traj.at(t0 + t_s); };
}

MockPoseSource::MockPoseSource(MockPoseSourceConfig config) : config_(std::move(config)) {}

MockPoseSource::~MockPoseSource() {
  stop();
}

void MockPoseSource::open() {
  if (!config_.motion)
    throw DeviceError("mock pose source '" + config_.id + "': no motion or trajectory given");
  if (!(config_.rate_hz > 0 && config_.rate_hz <= 100'000))
    throw DeviceError("mock pose source '" + config_.id + "': rate_hz " +
                      std::to_string(config_.rate_hz) + " outside (0, 100000]");
  opened_ = true;
}

PoseSample MockPoseSource::sample_at(double t_s) const {
  constexpr double kH = 1e-4;  // central difference step (s)
  const TrajectorySample s = config_.motion(t_s);
  const Eigen::Quaterniond qa = config_.motion(t_s - kH).q;
  const Eigen::Quaterniond qb = config_.motion(t_s + kH).q;
  // Head-frame angular velocity: R(t)^T dR/dt, from the relative rotation over 2h.
  const Eigen::AngleAxisd d(qa.conjugate() * qb);
  PoseSample out;
  out.T_tracker_head = core::Pose::from(s.q, s.position_m);
  out.angular_velocity_rad_s = d.axis() * (d.angle() / (2 * kH));
  out.has_angular_velocity = true;
  out.has_position = config_.has_position;
  out.device_time_trusted = true;  // simulated time is exact
  return out;
}

void MockPoseSource::start() {
  if (running_) return;
  if (!opened_) open();
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void MockPoseSource::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
}

SourceState MockPoseSource::state() const {
  if (!running_) return SourceState::kClosed;
  const int64_t last = last_publish_ns_.load(std::memory_order_acquire);
  if (last != 0 && monotonic_now_ns() - last > config_.stall_timeout_ns)
    return SourceState::kStalled;
  return SourceState::kStreaming;
}

void MockPoseSource::run() {
  const auto period_ns = static_cast<int64_t>(std::llround(1e9 / config_.rate_hz));
  int64_t start_ns = monotonic_now_ns();
  int64_t first_ns = start_ns;
  if (config_.epoch_ns) {
    start_ns = config_.epoch_ns();  // t_s counts from the shared epoch
    const int64_t behind = first_ns - start_ns;
    first_ns = behind <= 0 ? start_ns : start_ns + (behind + period_ns - 1) / period_ns * period_ns;
  }
  for (uint64_t seq = 0; running_.load(std::memory_order_relaxed); ++seq) {
    const int64_t due_ns = first_ns + static_cast<int64_t>(seq) * period_ns;
    const int64_t wait_ns = due_ns - monotonic_now_ns();
    if (wait_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait_ns));
    PoseSample& s = latest_.write_slot();
    s = sample_at(static_cast<double>(due_ns - start_ns) * 1e-9);
    s.sequence = seq;
    s.host_timestamp_ns = due_ns;
    s.device_timestamp_ns = due_ns - start_ns;
    if (config_.sample_filter)
      config_.sample_filter(s, static_cast<double>(due_ns - start_ns) * 1e-9);
    history_.push(s);
    latest_.publish();
    last_publish_ns_.store(monotonic_now_ns(), std::memory_order_release);
  }
}

}  // namespace hd::drivers
