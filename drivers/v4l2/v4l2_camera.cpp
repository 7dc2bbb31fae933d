#include "drivers/v4l2/v4l2_camera.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <system_error>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/convert/yuyv_to_rgba.h"

namespace hd::drivers {
namespace {

std::string errno_text(int err) {
  return std::error_code(err, std::generic_category()).message();
}

std::string mode_text(uint32_t fourcc, int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h) + " " + v4l2_fourcc_name(fourcc);
}

// A reopen found the driver answering another mode than the one streamed: not a lost device.
class ModeChanged : public DeviceError {
 public:
  ModeChanged(const std::string& what, CameraFormat seen) : DeviceError(what), seen_(seen) {}
  const CameraFormat& seen() const { return seen_; }

 private:
  CameraFormat seen_;
};

CameraFormat format_of(uint32_t fourcc, int w, int h, double fps) {
  // A fourcc we do not convert has no PixelFormat; RGBA8 (never a V4L2 capture format here)
  // stands for "another one".
  return {w, h, v4l2_fourcc_supported(fourcc) ? v4l2_pixel_format(fourcc) : PixelFormat::kRgba8,
          fps};
}

}  // namespace

V4l2Camera::V4l2Camera(std::string device_path, V4l2CameraOptions options, V4l2Syscalls& sys)
    : path_(std::move(device_path)),
      options_(options),
      sys_(sys),
      mailbox_(std::make_unique<Mailbox<Frame>>()) {}

V4l2Camera::~V4l2Camera() {
  stop();
}

void V4l2Camera::fail(const std::string& what, int err) const {
  std::string msg = path_ + ": " + what;
  if (err != 0) msg += ": " + errno_text(err);
  if (err == EACCES || err == EPERM) {
    msg +=
        " (install udev/70-hybrid-station.rules, or add the user to the 'video' group and log "
        "in again)";
  }
  throw DeviceError(msg);
}

std::string V4l2Camera::last_error() const {
  std::lock_guard lock(error_mutex_);
  return last_error_;
}

void V4l2Camera::set_error(std::string message) {
  spdlog::warn("{}", message);
  std::lock_guard lock(error_mutex_);
  last_error_ = std::move(message);
}

void V4l2Camera::open() {
  if (thread_.joinable()) fail("open() while streaming; stop() first");
  close_stream(false);
  open_stream(false);
}

FormatNegotiation V4l2Camera::negotiate(const CameraFormatRequest& wanted) {
  if (thread_.joinable()) fail("negotiate() while streaming; stop() first");
  if (wanted.width_px > 0 && wanted.height_px > 0) {
    options_.mode.width_px = wanted.width_px;
    options_.mode.height_px = wanted.height_px;
  }
  if (wanted.frame_rate_hz > 0.0) options_.mode.fps = wanted.frame_rate_hz;
  if (!wanted.pixel_formats.empty()) {
    const auto has = [&](PixelFormat f) {
      return std::find(wanted.pixel_formats.begin(), wanted.pixel_formats.end(), f) !=
             wanted.pixel_formats.end();
    };
    if (has(PixelFormat::kYuyv) && has(PixelFormat::kMjpeg))
      options_.mode.fourcc = 0;
    else if (has(PixelFormat::kYuyv))
      options_.mode.fourcc = V4L2_PIX_FMT_YUYV;
    else if (has(PixelFormat::kMjpeg))
      options_.mode.fourcc = V4L2_PIX_FMT_MJPEG;
    else
      fail("none of the pixel formats asked for is one this driver converts (YUYV, MJPEG)");
  }
  open();
  FormatNegotiation n{format(), refused_, "", ""};
  std::vector<std::string> seen;
  for (const V4l2Mode& m : modes_) {
    if (!v4l2_fourcc_supported(m.fourcc)) continue;
    const std::string t = mode_text(m.fourcc, m.width_px, m.height_px);
    if (std::find(seen.begin(), seen.end(), t) != seen.end()) continue;
    seen.push_back(t);
    n.limits += (n.limits.empty() ? "" : ", ") + t;
  }
  return n;
}

CameraFormat V4l2Camera::format() const {
  if (chosen_.width_px <= 0) return {};
  return format_of(chosen_.fourcc, chosen_.width_px, chosen_.height_px, chosen_.interval.fps());
}

void V4l2Camera::open_stream(bool reopening) {
  const int raw_fd = sys_.open(path_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (raw_fd < 0) fail("cannot open the video node", errno);
  UniqueFd fd(sys_, raw_fd);

  v4l2_capability cap{};
  if (sys_.ioctl(fd.get(), VIDIOC_QUERYCAP, &cap) != 0) {
    fail("VIDIOC_QUERYCAP failed (not a V4L2 device?)", errno);
  }
  // device_caps describes this node; capabilities is the union over the whole physical device.
  const uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0) {
    fail("not a video capture node (device_caps lack VIDEO_CAPTURE; a UVC metadata node?)");
  }
  if ((caps & V4L2_CAP_STREAMING) == 0) fail("does not support streaming I/O (device_caps)");

  V4l2ModeRequest request = options_.mode;
  if (reopening) {  // the mailbox is sized: only the same mode may resume
    request.fourcc = chosen_.fourcc;
    request.width_px = chosen_.width_px;
    request.height_px = chosen_.height_px;
  }
  std::vector<V4l2Mode> modes = enumerate_v4l2_modes(sys_, fd.get(), request);
  const std::optional<V4l2ModeChoice> choice = choose_v4l2_mode(modes, request);
  if (!choice) {
    std::string offered;
    for (const auto& m : modes) offered += " " + mode_text(m.fourcc, m.width_px, m.height_px);
    fail("offers no mode we can convert (we take YUYV or MJPEG); offered:" +
         (offered.empty() ? std::string(" nothing") : offered));
  }
  V4l2ModeChoice chosen = *choice;
  std::string refused;
  if (chosen.width_px != request.width_px || chosen.height_px != request.height_px) {
    refused = "it offers no " + std::to_string(request.width_px) + "x" +
              std::to_string(request.height_px) + " mode";
  }

  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<uint32_t>(chosen.width_px);
  fmt.fmt.pix.height = static_cast<uint32_t>(chosen.height_px);
  fmt.fmt.pix.pixelformat = chosen.fourcc;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (sys_.ioctl(fd.get(), VIDIOC_S_FMT, &fmt) != 0) {
    fail("VIDIOC_S_FMT " + mode_text(chosen.fourcc, chosen.width_px, chosen.height_px) + " refused",
         errno);
  }
  // The driver writes back what it will really deliver; it may differ from what we asked.
  const auto& pix = fmt.fmt.pix;
  if (!v4l2_fourcc_supported(pix.pixelformat)) {
    fail("driver answered S_FMT " + mode_text(chosen.fourcc, chosen.width_px, chosen.height_px) +
         " with " + mode_text(pix.pixelformat, int(pix.width), int(pix.height)) +
         ", a format we cannot convert");
  }
  const int w = static_cast<int>(pix.width);
  const int h = static_cast<int>(pix.height);
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384) {
    fail("driver answered S_FMT with an impossible size " + mode_text(pix.pixelformat, w, h));
  }
  if (w != chosen.width_px || h != chosen.height_px || pix.pixelformat != chosen.fourcc) {
    if (!reopening) {
      spdlog::info("{}: asked for {}, driver gives {}; adopting it", path_,
                   mode_text(chosen.fourcc, chosen.width_px, chosen.height_px),
                   mode_text(pix.pixelformat, w, h));
    }
    refused += (refused.empty() ? "" : "; ") + std::string("VIDIOC_S_FMT ") +
               mode_text(chosen.fourcc, chosen.width_px, chosen.height_px) + " answered " +
               mode_text(pix.pixelformat, w, h);
  }
  chosen.fourcc = pix.pixelformat;
  chosen.width_px = w;
  chosen.height_px = h;
  int bytes_per_line = static_cast<int>(pix.bytesperline);
  if (chosen.fourcc == V4L2_PIX_FMT_YUYV) {
    if (w % 2 != 0) fail("driver answered S_FMT with an odd YUYV width " + std::to_string(w));
    if (bytes_per_line == 0) bytes_per_line = 2 * w;
    if (bytes_per_line < 2 * w) {
      fail("driver answered S_FMT with bytesperline " + std::to_string(bytes_per_line) +
           " < 2 x width " + std::to_string(w));
    }
  }
  if (reopening &&
      (chosen.fourcc != chosen_.fourcc || w != chosen_.width_px || h != chosen_.height_px)) {
    throw ModeChanged(path_ + ": came back as " + mode_text(chosen.fourcc, w, h) +
                          " but was streaming " +
                          mode_text(chosen_.fourcc, chosen_.width_px, chosen_.height_px),
                      format_of(chosen.fourcc, w, h, 0.0));
  }

  if (chosen.interval.numerator != 0) {
    v4l2_streamparm parm{};
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    parm.parm.capture.timeperframe = {chosen.interval.numerator, chosen.interval.denominator};
    if (sys_.ioctl(fd.get(), VIDIOC_S_PARM, &parm) == 0) {
      const auto& tpf = parm.parm.capture.timeperframe;
      if (tpf.numerator != 0 && tpf.denominator != 0) {
        chosen.interval = {tpf.numerator, tpf.denominator};
      }
    } else {
      // Not fatal: many drivers have one fixed rate and no S_PARM.
      spdlog::info("{}: VIDIOC_S_PARM not accepted ({}); using the driver's rate", path_,
                   errno_text(errno));
    }
  }

  // Drivers without source-change events (most UVC ones) refuse this; frames of another size
  // then still never pass the converters, which check every buffer's length.
  v4l2_event_subscription sub{};
  sub.type = V4L2_EVENT_SOURCE_CHANGE;
  events_subscribed_.store(sys_.ioctl(fd.get(), VIDIOC_SUBSCRIBE_EVENT, &sub) == 0);

  v4l2_requestbuffers req{};
  req.count = static_cast<uint32_t>(options_.buffer_count);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (sys_.ioctl(fd.get(), VIDIOC_REQBUFS, &req) != 0) fail("VIDIOC_REQBUFS (mmap) failed", errno);
  if (req.count < 2) fail("driver granted only " + std::to_string(req.count) + " buffer(s)");
  std::vector<MmapBuffer> buffers;
  buffers.reserve(req.count);
  for (uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (sys_.ioctl(fd.get(), VIDIOC_QUERYBUF, &b) != 0) {
      fail("VIDIOC_QUERYBUF " + std::to_string(i) + " failed", errno);
    }
    buffers.emplace_back(sys_, fd.get(), b.length, static_cast<off_t>(b.m.offset));
    if (!buffers.back().valid()) fail("mmap of buffer " + std::to_string(i) + " failed", errno);
  }

  // Everything below is allocation for the stream; the per-frame path only reuses it.
  if (chosen.fourcc != V4L2_PIX_FMT_YUYV) {
    if (!mjpeg_) mjpeg_ = std::make_unique<MjpegDecoder>();
    mjpeg_->reserve(std::max<std::size_t>(pix.sizeimage, buffers.front().size()));
  }
  const Frame& current = mailbox_->write_slot();
  if (current.width != w || current.height != h || current.data.empty()) {
    Frame prototype;
    prototype.allocate_rgba(w, h);
    mailbox_ = std::make_unique<Mailbox<Frame>>(prototype);
  }
  if (!reopening) {  // the consumer may read these while the capture thread reopens
    modes_ = std::move(modes);
    chosen_ = chosen;
    refused_ = refused;
    format_watch_.forget();
  }
  bytes_per_line_ = bytes_per_line;
  size_image_ = pix.sizeimage;
  buffers_ = std::move(buffers);
  fd_ = std::move(fd);
}

void V4l2Camera::start_stream() {
  for (uint32_t i = 0; i < buffers_.size(); ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (sys_.ioctl(fd_.get(), VIDIOC_QBUF, &b) != 0) {
      fail("VIDIOC_QBUF " + std::to_string(i) + " failed", errno);
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (sys_.ioctl(fd_.get(), VIDIOC_STREAMON, &type) != 0) fail("VIDIOC_STREAMON failed", errno);
  streaming_ = true;
  have_sequence_ = false;
  last_frame_ns_ = monotonic_now_ns();
}

void V4l2Camera::close_stream(bool device_gone) {
  if (fd_.valid() && !device_gone) {
    if (streaming_) {
      int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      sys_.ioctl(fd_.get(), VIDIOC_STREAMOFF, &type);
    }
  }
  streaming_ = false;
  buffers_.clear();  // munmap before freeing the driver's buffers
  if (fd_.valid() && !device_gone) {
    v4l2_requestbuffers req{};
    req.count = 0;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    sys_.ioctl(fd_.get(), VIDIOC_REQBUFS, &req);
  }
  fd_.reset();
}

void V4l2Camera::start() {
  if (thread_.joinable()) return;
  if (!fd_.valid()) open_stream(false);
  try {
    start_stream();
  } catch (...) {
    close_stream(false);
    throw;
  }
  set_state(SourceState::kStreaming);
  stop_requested_.store(false);
  thread_ = std::thread([this] { run(); });
}

void V4l2Camera::stop() {
  stop_requested_.store(true);
  if (thread_.joinable()) thread_.join();
  close_stream(false);
  set_state(SourceState::kClosed);
}

void V4l2Camera::run() {
  while (!stop_requested_.load(std::memory_order_relaxed)) {
    if (!fd_.valid()) {
      try_reopen();
      continue;
    }
    pollfd p{fd_.get(), static_cast<short>(POLLIN | POLLPRI), 0};
    const int r = sys_.poll(&p, 1, options_.poll_timeout_ms);
    if (r < 0) {
      const int err = errno;
      if (err != EINTR) lose_device(err, "poll");
      continue;
    }
    // Events first: a buffer dequeued after a source change may hold the new format.
    if (r > 0 && (p.revents & POLLPRI) != 0) handle_events();
    if (r > 0 && fd_.valid() && (p.revents & ~POLLPRI) != 0) capture_once(p.revents);
    if (fd_.valid() && state() == SourceState::kStreaming &&
        monotonic_now_ns() - last_frame_ns_ > options_.stall_timeout_ns) {
      set_state(SourceState::kStalled);
    }
  }
}

void V4l2Camera::capture_once(short revents) {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (sys_.ioctl(fd_.get(), VIDIOC_DQBUF, &b) != 0) {
    const int err = errno;
    if (err == EAGAIN) {
      eagain_.fetch_add(1, std::memory_order_relaxed);
      // Readable-with-error and nothing to dequeue: the node is dead even if no ENODEV came.
      if ((revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) lose_device(ENODEV, "poll");
      return;
    }
    if (err == EINTR) return;
    if (err == EIO) {  // transient per the V4L2 spec (e.g. signal loss); a stall shows if not
      error_buffers_.fetch_add(1, std::memory_order_relaxed);
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    lose_device(err, "VIDIOC_DQBUF");
    return;
  }
  if (b.index >= buffers_.size()) {
    lose_device(EINVAL, "VIDIOC_DQBUF (buffer index out of range)");
    return;
  }
  const int64_t now_ns = monotonic_now_ns();

  // Sequence: 32-bit on the wire, unwrapped by modular difference; gaps are frames the driver
  // lost (no buffer was free or the USB transfer failed).
  if (!have_sequence_) {
    have_sequence_ = true;
    dev_sequence_ = published_any_ ? last_published_seq_ + 1 : b.sequence;
  } else {
    const uint32_t diff = b.sequence - last_sequence32_;
    if (diff >= 1 && diff < 0x80000000u) {
      if (diff > 1) {
        gap_frames_.fetch_add(diff - 1, std::memory_order_relaxed);
        dropped_.fetch_add(diff - 1, std::memory_order_relaxed);
      }
      dev_sequence_ += diff;
    } else {
      dev_sequence_ += 1;  // repeated or backwards: a driver restart, not a loss
    }
  }
  last_sequence32_ = b.sequence;

  if ((b.flags & V4L2_BUF_FLAG_ERROR) != 0) {
    error_buffers_.fetch_add(1, std::memory_order_relaxed);
    dropped_.fetch_add(1, std::memory_order_relaxed);
  } else {
    const MmapBuffer& buf = buffers_[b.index];
    const std::size_t len = b.bytesused;
    Frame& f = mailbox_->write_slot();
    bool ok = len > 0 && len <= buf.size();
    if (ok) {
      if (chosen_.fourcc == V4L2_PIX_FMT_YUYV) {
        ok = yuyv_to_rgba(buf.data(), len, f.width, f.height, bytes_per_line_, f.data.data(),
                          f.data.size(), f.stride_bytes);
      } else {
        ok = mjpeg_->decode_rgba(buf.data(), len, f.width, f.height, f.data.data(), f.data.size(),
                                 f.stride_bytes);
      }
    }
    if (ok) {
      const int64_t ts_ns =
          int64_t(b.timestamp.tv_sec) * 1'000'000'000 + int64_t(b.timestamp.tv_usec) * 1'000;
      const bool monotonic =
          (b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
      f.sequence = dev_sequence_;
      f.device_timestamp_ns = ts_ns;
      // A monotonic stamp is already on our clock (taken by the kernel at the first USB packet);
      // one from the future is not believable.
      f.device_time_trusted = monotonic && ts_ns > 0 && ts_ns <= now_ns;
      f.host_timestamp_ns = f.device_time_trusted ? ts_ns : now_ns;
      mailbox_->publish();
      last_published_seq_ = dev_sequence_;
      published_any_ = true;
      last_frame_ns_ = now_ns;
      if (state() != SourceState::kStreaming) set_state(SourceState::kStreaming);
    } else {
      bad_frames_.fetch_add(1, std::memory_order_relaxed);
      dropped_.fetch_add(1, std::memory_order_relaxed);
    }
  }

  v4l2_buffer q{};
  q.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  q.memory = V4L2_MEMORY_MMAP;
  q.index = b.index;
  if (sys_.ioctl(fd_.get(), VIDIOC_QBUF, &q) != 0) lose_device(errno, "VIDIOC_QBUF");
}

void V4l2Camera::lose_device(int err, const char* what) {
  set_error(path_ + ": " + what + " failed: " + errno_text(err) +
            "; device lost, reopening every " +
            std::to_string(options_.reopen_period_ns / 1'000'000) + " ms");
  close_stream(err == ENODEV);
  have_sequence_ = false;
  last_reopen_try_ns_ = monotonic_now_ns();
  set_state(SourceState::kDisconnected);
}

void V4l2Camera::try_reopen() {
  const int64_t now_ns = monotonic_now_ns();
  const int64_t wait_ns = last_reopen_try_ns_ + options_.reopen_period_ns - now_ns;
  if (wait_ns > 0) {
    // Short naps keep stop() responsive.
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::min<int64_t>(wait_ns, 10'000'000)));
    return;
  }
  last_reopen_try_ns_ = now_ns;
  reopen_attempts_.fetch_add(1, std::memory_order_relaxed);
  try {
    open_stream(true);
    start_stream();
  } catch (const ModeChanged& e) {
    close_stream(false);
    if (!format_watch_.is_lost())
      set_error(std::string(e.what()) + "; unusable until it does again");
    enter_mismatch(FormatEventCause::kReconnect, e.seen(), monotonic_now_ns());
    return;
  } catch (const DeviceError& e) {
    close_stream(false);
    // A node that is gone is disconnected, whatever its format was.
    if (state() == SourceState::kFormatMismatch) set_state(SourceState::kDisconnected);
    std::lock_guard lock(error_mutex_);
    last_error_ = e.what();  // the node is usually just absent: not worth a log line per try
    return;
  }
  reconnects_.fetch_add(1, std::memory_order_relaxed);
  spdlog::info("{}: reopened, streaming {} again", path_,
               mode_text(chosen_.fourcc, chosen_.width_px, chosen_.height_px));
  leave_mismatch(monotonic_now_ns());
  set_state(SourceState::kStreaming);
}

void V4l2Camera::handle_events() {
  bool changed = false;
  int64_t when_ns = 0;
  for (int i = 0; i < 64; ++i) {  // bounded: a driver that floods events cannot hold us here
    v4l2_event ev{};
    if (sys_.ioctl(fd_.get(), VIDIOC_DQEVENT, &ev) != 0) break;  // ENOENT: none left
    if (ev.type == V4L2_EVENT_SOURCE_CHANGE &&
        (ev.u.src_change.changes & V4L2_EVENT_SRC_CH_RESOLUTION) != 0) {
      changed = true;
      // Event timestamps are CLOCK_MONOTONIC (V4L2 spec, VIDIOC_DQEVENT).
      when_ns = int64_t(ev.timestamp.tv_sec) * 1'000'000'000 + int64_t(ev.timestamp.tv_nsec);
    }
  }
  if (!changed) return;
  const int64_t now_ns = monotonic_now_ns();
  if (when_ns <= 0 || when_ns > now_ns) when_ns = now_ns;
  CameraFormat seen;
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (sys_.ioctl(fd_.get(), VIDIOC_G_FMT, &fmt) == 0) {
    seen = format_of(fmt.fmt.pix.pixelformat, int(fmt.fmt.pix.width), int(fmt.fmt.pix.height), 0.0);
  }
  set_error(path_ + ": the source changed (V4L2_EVENT_SOURCE_CHANGE, now " + format_text(seen) +
            "); unusable, reopening every " +
            std::to_string(options_.reopen_period_ns / 1'000'000) + " ms until it delivers " +
            format_text(format()) + " again");
  enter_mismatch(FormatEventCause::kSourceChange, seen, when_ns);
  close_stream(false);
  have_sequence_ = false;
  last_reopen_try_ns_ = now_ns;
}

void V4l2Camera::enter_mismatch(FormatEventCause cause, const CameraFormat& seen, int64_t when_ns) {
  // State first: a consumer that sees the event must also see the camera as unusable.
  set_state(SourceState::kFormatMismatch);
  format_watch_.lost(when_ns, cause, format(), seen);
}

void V4l2Camera::leave_mismatch(int64_t now_ns) {
  format_watch_.restored(now_ns, FormatEventCause::kReconnect, format());
}

}  // namespace hd::drivers
