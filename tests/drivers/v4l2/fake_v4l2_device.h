#pragma once
// A V4L2 capture device as a state machine behind the syscall seam: the real V4l2Camera code runs
// against it unchanged. It implements the protocol the camera relies on (QUERYCAP, ENUM_*, S_FMT,
// S_PARM, REQBUFS, QUERYBUF, mmap, QBUF, DQBUF, STREAMON/OFF, poll) and checks the caller's side
// of it (buffer ownership, unmapping before freeing). Faults are scripted by frame index. Source
// changes (a capture device whose input changes resolution) raise V4L2_EVENT_SOURCE_CHANGE for
// subscribed handles, with POLLPRI, VIDIOC_DQEVENT and G_FMT reporting the new size.

#include <linux/videodev2.h>

#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers::testing {

struct FakeMode {
  uint32_t fourcc = V4L2_PIX_FMT_YUYV;
  uint32_t width = 32;
  uint32_t height = 16;
  std::vector<std::pair<uint32_t, uint32_t>> intervals{{1, 30}};  // numerator, denominator
};

struct FakeV4l2Config {
  std::string path = "/dev/video-fake";
  std::string card = "Fake UVC Camera";
  uint32_t device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
  std::vector<FakeMode> modes{FakeMode{}};
  // A driver that does not do what it is asked: S_FMT answers with this instead.
  std::optional<std::pair<uint32_t, uint32_t>> force_size;
  std::optional<uint32_t> force_fourcc;
  uint32_t bytesperline_pad = 0;  // extra bytes per YUYV row
  uint32_t max_buffers = 4;
  bool monotonic_timestamps = true;
  int frame_period_us = 1000;  // how long poll waits for the next frame
  int open_errno = 0;          // nonzero: open() fails with it (permissions, busy)
  std::vector<std::vector<uint8_t>> mjpeg_frames;  // MJPEG payloads, used round-robin

  // Scripted faults, keyed by the index of the frame the fake is about to produce.
  std::set<uint64_t> eagain_before;          // one poll wake-up whose DQBUF returns EAGAIN
  std::set<uint64_t> error_at;               // buffer returned with V4L2_BUF_FLAG_ERROR
  std::map<uint64_t, uint32_t> skip_before;  // sequence jumps by this many (frames lost)
  std::set<uint64_t> truncate_at;            // payload cut to a third (corrupt MJPEG / short YUYV)
  std::optional<uint64_t> unplug_at;         // device disappears instead of producing this frame
  bool unplug_fails_poll = false;    // after unplug poll() fails with ENODEV (else POLLERR|POLLHUP)
  std::optional<uint64_t> stall_at;  // no more frames until resume()
  // The source changes to this size instead of producing this frame normally: the frame is
  // produced at the new size (into the old buffers when it fits, else flagged ERROR), an event
  // is queued, and S_FMT answers the new size from then on (until change_source()).
  std::optional<uint64_t> source_change_at;
  std::pair<uint32_t, uint32_t> source_change_to{16, 32};
};

/// The YUYV byte the fake writes at (byte column x, row y) of frame `sequence`: tests recompute
/// the expected image from a frame's sequence number.
uint8_t fake_yuyv_byte(uint64_t sequence, uint32_t x_byte, uint32_t y);

class FakeV4l2Device final : public V4l2Syscalls {
 public:
  explicit FakeV4l2Device(FakeV4l2Config config);

  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;
  void* mmap(void* addr, std::size_t length, int prot, int flags, int fd, off_t offset) override;
  int munmap(void* addr, std::size_t length) override;

  void replug();  ///< the node comes back (a new device instance, sequence from 0)
  void resume();  ///< frames flow again after a scripted stall
  /// The source now has this size (S_FMT answers it), with an event for subscribed handles.
  void change_source(uint32_t width, uint32_t height);

  int open_fds() const;
  int mapped_buffers() const;
  uint64_t frames_produced() const;
  uint64_t qbuf_calls() const;
  uint64_t events_raised() const;
  bool streaming() const;
  v4l2_pix_format last_requested_format() const;
  std::optional<std::pair<uint32_t, uint32_t>> last_timeperframe() const;

 private:
  struct Buffer {
    std::vector<uint8_t> memory;
    int mapped = 0;
    bool queued = false;  // owned by the driver, waiting to be filled
    bool done = false;    // filled, waiting for DQBUF
    v4l2_buffer info{};
  };

  int ioctl_locked(int fd, unsigned long request, void* arg);
  bool produce_locked();  // fills the oldest queued buffer; false when it cannot
  void unplug_locked();
  void change_source_locked(uint32_t width, uint32_t height);
  std::size_t frame_bytes_locked() const;
  short pending_locked(const pollfd& p) const;  // POLLPRI when p asked for it and an event waits

  FakeV4l2Config config_;
  mutable std::mutex mutex_;
  std::set<int> fds_;
  std::set<int> dead_fds_;  // opened before an unplug: ENODEV from now on
  int next_fd_ = 100;
  bool unplugged_ = false;
  bool stalled_ = false;
  bool eagain_pending_ = false;
  bool streaming_ = false;
  std::vector<Buffer> buffers_;
  std::deque<uint32_t> incoming_;
  std::deque<uint32_t> done_;
  v4l2_pix_format format_{};
  v4l2_pix_format last_request_{};
  std::optional<std::pair<uint32_t, uint32_t>> timeperframe_;
  uint64_t produced_ = 0;  // frame index across the device's life (for scripted faults)
  uint32_t sequence_ = 0;  // per device instance, as drivers do
  uint64_t qbuf_calls_ = 0;
  std::optional<std::pair<uint32_t, uint32_t>> source_size_;  // after a source change
  std::set<int> subscribed_;                                  // fds with SOURCE_CHANGE events
  std::map<int, std::deque<v4l2_event>> pending_events_;
  uint32_t event_sequence_ = 0;
  uint64_t events_raised_ = 0;
};

}  // namespace hd::drivers::testing
