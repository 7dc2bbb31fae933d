#pragma once
// A USB (UVC) camera through raw V4L2 ioctls: mmap streaming, YUYV or MJPEG to RGBA8.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/camera_source.h"
#include "drivers/convert/mjpeg_decoder.h"
#include "drivers/format_watch.h"
#include "drivers/v4l2/mmap_buffer.h"
#include "drivers/v4l2/unique_fd.h"
#include "drivers/v4l2/v4l2_mode.h"
#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers {

struct V4l2CameraOptions {
  V4l2ModeRequest mode;
  int buffer_count = 4;                    ///< REQBUFS asks for this many; >= 2 accepted
  int poll_timeout_ms = 50;                ///< bounds how long stop() waits for the thread
  int64_t stall_timeout_ns = 500'000'000;  ///< no frame for this long: kStalled
  int64_t reopen_period_ns = 500'000'000;  ///< retry period while disconnected
};

/// open() queries the node, negotiates a mode (see choose_v4l2_mode), sets it with S_FMT and
/// adopts the driver's answer (a different size is adopted, and negotiate() says so; a format we
/// cannot convert is refused), sets the rate with S_PARM and maps the buffers. start() streams on
/// a thread that converts every frame into the mailbox's write slot and publishes it. After
/// start() the per-frame path neither allocates nor locks.
///
/// Faults: sequence gaps, error-flagged buffers and frames that fail to convert are dropped and
/// counted; ENODEV or any other stream failure closes everything (kDisconnected) and the thread
/// reopens the node every reopen_period until the same mode streams again (kStreaming).
///
/// Format changes: the camera subscribes to V4L2_EVENT_SOURCE_CHANGE (where the driver has it)
/// and handles events before it dequeues a buffer. A resolution change, or a reopen whose S_FMT
/// answers another mode, makes the state kFormatMismatch at once with a FormatEvent (the event's
/// time is the kernel's, CLOCK_MONOTONIC), closes the stream and publishes nothing; the node is
/// reopened with the negotiated mode every reopen_period until the driver delivers it again.
class V4l2Camera final : public CameraSource {
 public:
  explicit V4l2Camera(std::string device_path, V4l2CameraOptions options = {},
                      V4l2Syscalls& sys = libc_v4l2_syscalls());
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  std::string id() const override { return path_; }
  void open() override;  ///< throws DeviceError naming the device
  /// The request's size, rate and (YUYV and/or MJPEG) formats replace the options' mode; the
  /// driver's S_FMT answer is returned. Before start() only.
  FormatNegotiation negotiate(const CameraFormatRequest& wanted) override;
  CameraFormat format() const override;
  bool pop_format_event(FormatEvent& out) override { return format_watch_.pop(out); }
  void start() override;  ///< opens first if needed; throws DeviceError
  void stop() override;   ///< joins the thread, releases every buffer and the fd
  SourceState state() const override { return state_.load(std::memory_order_acquire); }
  uint64_t dropped_frames() const override { return dropped_.load(std::memory_order_relaxed); }
  Mailbox<Frame>& frames() override { return *mailbox_; }

  /// The negotiated mode (after open(); a reopen must match it).
  const V4l2ModeChoice& mode() const { return chosen_; }
  /// Everything the device offered at the last open().
  const std::vector<V4l2Mode>& offered_modes() const { return modes_; }

  uint64_t error_buffers() const { return error_buffers_.load(std::memory_order_relaxed); }
  uint64_t bad_frames() const { return bad_frames_.load(std::memory_order_relaxed); }
  uint64_t sequence_gaps() const { return gap_frames_.load(std::memory_order_relaxed); }
  uint64_t spurious_wakeups() const { return eagain_.load(std::memory_order_relaxed); }
  uint64_t reconnects() const { return reconnects_.load(std::memory_order_relaxed); }
  /// Reopen attempts while disconnected or mismatched (successful or not).
  uint64_t reopen_attempts() const { return reopen_attempts_.load(std::memory_order_relaxed); }
  /// Whether the driver accepted the V4L2_EVENT_SOURCE_CHANGE subscription at the last open.
  bool source_change_events() const { return events_subscribed_.load(); }
  /// Why the device last failed (empty if it never did). Not for the per-frame path.
  std::string last_error() const;

 private:
  void open_stream(bool reopening);  // throws DeviceError
  void start_stream();               // throws DeviceError
  void close_stream(bool device_gone);
  void run();
  void capture_once(short revents);
  void handle_events();
  void enter_mismatch(FormatEventCause cause, const CameraFormat& seen, int64_t when_ns);
  void leave_mismatch(int64_t now_ns);
  void lose_device(int err, const char* what);
  void try_reopen();
  void set_error(std::string message);
  void set_state(SourceState s) { state_.store(s, std::memory_order_release); }
  [[noreturn]] void fail(const std::string& what, int err = 0) const;

  std::string path_;
  V4l2CameraOptions options_;
  V4l2Syscalls& sys_;

  UniqueFd fd_;
  std::vector<MmapBuffer> buffers_;
  bool streaming_ = false;
  std::vector<V4l2Mode> modes_;
  V4l2ModeChoice chosen_;
  int bytes_per_line_ = 0;
  std::size_t size_image_ = 0;
  std::unique_ptr<Mailbox<Frame>> mailbox_;
  std::unique_ptr<MjpegDecoder> mjpeg_;
  std::string refused_;  // what the last open's driver did not take (for negotiate())
  std::atomic<bool> events_subscribed_{false};
  FormatWatch format_watch_;  // capture thread; the station pops its events

  std::thread thread_;
  std::atomic<bool> stop_requested_{false};
  std::atomic<SourceState> state_{SourceState::kClosed};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<uint64_t> error_buffers_{0};
  std::atomic<uint64_t> bad_frames_{0};
  std::atomic<uint64_t> gap_frames_{0};
  std::atomic<uint64_t> eagain_{0};
  std::atomic<uint64_t> reconnects_{0};
  std::atomic<uint64_t> reopen_attempts_{0};

  // Capture-thread state.
  bool have_sequence_ = false;
  uint32_t last_sequence32_ = 0;
  uint64_t dev_sequence_ = 0;  // unwrapped; continues from the last frame across reconnects
  uint64_t last_published_seq_ = 0;
  bool published_any_ = false;
  int64_t last_frame_ns_ = 0;
  int64_t last_reopen_try_ns_ = 0;

  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace hd::drivers
