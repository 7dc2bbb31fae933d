#include "fake_v4l2_device.h"

#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace hd::drivers::testing {
namespace {

int fail(int err) {
  errno = err;
  return -1;
}

void copy_string(uint8_t* dst, std::size_t cap, const std::string& s) {
  std::memset(dst, 0, cap);
  std::memcpy(dst, s.data(), std::min(cap - 1, s.size()));
}

}  // namespace

uint8_t fake_yuyv_byte(uint64_t sequence, uint32_t x_byte, uint32_t y) {
  if (x_byte % 2 == 0) return static_cast<uint8_t>(16 + (x_byte * 5 + y * 11 + sequence * 3) % 220);
  return static_cast<uint8_t>(16 + (x_byte * 13 + y * 7 + sequence) % 225);
}

FakeV4l2Device::FakeV4l2Device(FakeV4l2Config config) : config_(std::move(config)) {}

int FakeV4l2Device::open(const char* path, int /*flags*/) {
  std::lock_guard lock(mutex_);
  if (config_.open_errno != 0) return fail(config_.open_errno);
  if (unplugged_ || config_.path != path) return fail(ENOENT);
  const int fd = next_fd_++;
  fds_.insert(fd);
  return fd;
}

int FakeV4l2Device::close(int fd) {
  std::lock_guard lock(mutex_);
  subscribed_.erase(fd);
  pending_events_.erase(fd);
  if (dead_fds_.erase(fd) == 1) return 0;
  if (fds_.erase(fd) == 0) return fail(EBADF);
  if (fds_.empty()) {  // last close releases the stream, and unmapped buffers
    streaming_ = false;
    incoming_.clear();
    done_.clear();
    const bool any_mapped =
        std::any_of(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped > 0; });
    if (!any_mapped) buffers_.clear();
  }
  return 0;
}

int FakeV4l2Device::ioctl(int fd, unsigned long request, void* arg) {
  std::lock_guard lock(mutex_);
  if (dead_fds_.count(fd) != 0) return fail(ENODEV);
  if (fds_.count(fd) == 0) return fail(EBADF);
  return ioctl_locked(fd, request, arg);
}

std::size_t FakeV4l2Device::frame_bytes_locked() const {
  return format_.sizeimage;
}

int FakeV4l2Device::ioctl_locked(int fd, unsigned long request, void* arg) {
  switch (request) {
    case VIDIOC_QUERYCAP: {
      auto* cap = static_cast<v4l2_capability*>(arg);
      *cap = {};
      copy_string(cap->driver, sizeof(cap->driver), "fakecam");
      copy_string(cap->card, sizeof(cap->card), config_.card);
      copy_string(cap->bus_info, sizeof(cap->bus_info), "usb-fake-1");
      cap->device_caps = config_.device_caps;
      cap->capabilities = config_.device_caps | V4L2_CAP_DEVICE_CAPS;
      return 0;
    }
    case VIDIOC_ENUM_FMT: {
      auto* f = static_cast<v4l2_fmtdesc*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      std::vector<uint32_t> fourccs;
      for (const auto& m : config_.modes) {
        if (std::find(fourccs.begin(), fourccs.end(), m.fourcc) == fourccs.end()) {
          fourccs.push_back(m.fourcc);
        }
      }
      if (f->index >= fourccs.size()) return fail(EINVAL);
      f->pixelformat = fourccs[f->index];
      f->flags = f->pixelformat == V4L2_PIX_FMT_MJPEG ? V4L2_FMT_FLAG_COMPRESSED : 0;
      return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
      auto* s = static_cast<v4l2_frmsizeenum*>(arg);
      uint32_t k = 0;
      for (const auto& m : config_.modes) {
        if (m.fourcc != s->pixel_format) continue;
        if (k++ == s->index) {
          s->type = V4L2_FRMSIZE_TYPE_DISCRETE;
          s->discrete = {m.width, m.height};
          return 0;
        }
      }
      return fail(EINVAL);
    }
    case VIDIOC_ENUM_FRAMEINTERVALS: {
      auto* e = static_cast<v4l2_frmivalenum*>(arg);
      for (const auto& m : config_.modes) {
        if (m.fourcc == e->pixel_format && m.width == e->width && m.height == e->height) {
          if (e->index >= m.intervals.size()) return fail(EINVAL);
          e->type = V4L2_FRMIVAL_TYPE_DISCRETE;
          e->discrete = {m.intervals[e->index].first, m.intervals[e->index].second};
          return 0;
        }
      }
      return fail(EINVAL);
    }
    case VIDIOC_G_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      f->fmt.pix = format_;
      return 0;
    }
    case VIDIOC_S_FMT: {
      auto* f = static_cast<v4l2_format*>(arg);
      if (f->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      if (streaming_ || !buffers_.empty()) return fail(EBUSY);
      last_request_ = f->fmt.pix;
      // Like real drivers: never fail, answer with the closest thing we have.
      const FakeMode* pick = &config_.modes.front();
      for (const auto& m : config_.modes) {
        if (m.fourcc == f->fmt.pix.pixelformat &&
            (pick->fourcc != m.fourcc ||
             (m.width == f->fmt.pix.width && m.height == f->fmt.pix.height))) {
          pick = &m;
        }
      }
      v4l2_pix_format p{};
      p.width = pick->width;
      p.height = pick->height;
      p.pixelformat = pick->fourcc;
      if (config_.force_size) std::tie(p.width, p.height) = *config_.force_size;
      if (source_size_) std::tie(p.width, p.height) = *source_size_;
      if (config_.force_fourcc) p.pixelformat = *config_.force_fourcc;
      p.field = V4L2_FIELD_NONE;
      if (p.pixelformat == V4L2_PIX_FMT_YUYV) {
        p.bytesperline = p.width * 2 + config_.bytesperline_pad;
        p.sizeimage = p.bytesperline * p.height;
      } else {
        std::size_t biggest = std::size_t(p.width) * p.height * 2;
        for (const auto& j : config_.mjpeg_frames) biggest = std::max(biggest, j.size());
        p.sizeimage = static_cast<uint32_t>(biggest);
      }
      format_ = p;
      f->fmt.pix = p;
      return 0;
    }
    case VIDIOC_S_PARM: {
      auto* parm = static_cast<v4l2_streamparm*>(arg);
      if (parm->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) return fail(EINVAL);
      const auto& want = parm->parm.capture.timeperframe;
      std::pair<uint32_t, uint32_t> got{1, 30};
      for (const auto& m : config_.modes) {
        if (m.fourcc != format_.pixelformat || m.width != format_.width) continue;
        if (!m.intervals.empty()) got = m.intervals.front();
        for (const auto& iv : m.intervals) {
          if (iv.first == want.numerator && iv.second == want.denominator) got = iv;
        }
      }
      timeperframe_ = got;
      parm->parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
      parm->parm.capture.timeperframe = {got.first, got.second};
      return 0;
    }
    case VIDIOC_REQBUFS: {
      auto* req = static_cast<v4l2_requestbuffers*>(arg);
      if (req->memory != V4L2_MEMORY_MMAP || req->type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return fail(EINVAL);
      }
      if (streaming_) return fail(EBUSY);
      for (const auto& b : buffers_) {
        if (b.mapped > 0) return fail(EBUSY);  // freeing mapped buffers: the caller's bug
      }
      buffers_.clear();
      incoming_.clear();
      done_.clear();
      req->count = std::min(req->count, config_.max_buffers);
      buffers_.resize(req->count);
      for (uint32_t i = 0; i < req->count; ++i) {
        Buffer& b = buffers_[i];
        b.memory.assign(frame_bytes_locked(), 0);
        b.info = {};
        b.info.index = i;
        b.info.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.info.memory = V4L2_MEMORY_MMAP;
        b.info.length = static_cast<uint32_t>(b.memory.size());
        b.info.m.offset = i * 0x100000u;
      }
      return 0;
    }
    case VIDIOC_QUERYBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->index >= buffers_.size()) return fail(EINVAL);
      *b = buffers_[b->index].info;
      return 0;
    }
    case VIDIOC_QBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (b->type != V4L2_BUF_TYPE_VIDEO_CAPTURE || b->memory != V4L2_MEMORY_MMAP ||
          b->index >= buffers_.size()) {
        return fail(EINVAL);
      }
      Buffer& buf = buffers_[b->index];
      if (buf.queued || buf.done) return fail(EINVAL);  // queued twice: the caller's bug
      buf.queued = true;
      incoming_.push_back(b->index);
      ++qbuf_calls_;
      return 0;
    }
    case VIDIOC_DQBUF: {
      auto* b = static_cast<v4l2_buffer*>(arg);
      if (eagain_pending_) {
        eagain_pending_ = false;
        return fail(EAGAIN);
      }
      if (!streaming_) return fail(EINVAL);
      if (done_.empty()) return fail(EAGAIN);
      const uint32_t idx = done_.front();
      done_.pop_front();
      buffers_[idx].done = false;
      *b = buffers_[idx].info;
      return 0;
    }
    case VIDIOC_STREAMON: {
      if (buffers_.empty()) return fail(EINVAL);
      streaming_ = true;
      return 0;
    }
    case VIDIOC_SUBSCRIBE_EVENT: {
      const auto* sub = static_cast<const v4l2_event_subscription*>(arg);
      if (sub->type != V4L2_EVENT_SOURCE_CHANGE || sub->id != 0) return fail(EINVAL);
      subscribed_.insert(fd);
      return 0;
    }
    case VIDIOC_UNSUBSCRIBE_EVENT: {
      subscribed_.erase(fd);
      pending_events_.erase(fd);
      return 0;
    }
    case VIDIOC_DQEVENT: {
      auto& queue = pending_events_[fd];
      if (queue.empty()) return fail(ENOENT);
      auto* ev = static_cast<v4l2_event*>(arg);
      *ev = queue.front();
      queue.pop_front();
      ev->pending = static_cast<uint32_t>(queue.size());
      return 0;
    }
    case VIDIOC_STREAMOFF: {
      streaming_ = false;
      incoming_.clear();
      done_.clear();
      for (auto& b : buffers_) b.queued = b.done = false;
      return 0;
    }
    default:
      return fail(ENOTTY);
  }
}

void FakeV4l2Device::unplug_locked() {
  unplugged_ = true;
  subscribed_.clear();
  pending_events_.clear();
  dead_fds_.insert(fds_.begin(), fds_.end());
  fds_.clear();
  streaming_ = false;
  incoming_.clear();
  done_.clear();
  for (auto& b : buffers_) b.queued = b.done = false;
}

void FakeV4l2Device::change_source_locked(uint32_t width, uint32_t height) {
  source_size_ = std::make_pair(width, height);
  // What G_FMT reports from now on; buffers already allocated keep their length.
  format_.width = width;
  format_.height = height;
  if (format_.pixelformat == V4L2_PIX_FMT_YUYV) {
    format_.bytesperline = width * 2 + config_.bytesperline_pad;
    format_.sizeimage = format_.bytesperline * height;
  }
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  for (int fd : subscribed_) {
    v4l2_event ev{};
    ev.type = V4L2_EVENT_SOURCE_CHANGE;
    ev.u.src_change.changes = V4L2_EVENT_SRC_CH_RESOLUTION;
    ev.sequence = event_sequence_++;
    ev.timestamp = ts;
    pending_events_[fd].push_back(ev);
    ++events_raised_;
  }
}

void FakeV4l2Device::change_source(uint32_t width, uint32_t height) {
  std::lock_guard lock(mutex_);
  change_source_locked(width, height);
}

bool FakeV4l2Device::produce_locked() {
  if (!streaming_ || incoming_.empty() || unplugged_ || stalled_) return false;
  const uint64_t n = produced_;
  if (config_.unplug_at && *config_.unplug_at == n) {
    config_.unplug_at.reset();
    unplug_locked();
    return false;
  }
  if (config_.stall_at && *config_.stall_at == n) {
    config_.stall_at.reset();
    stalled_ = true;
    return false;
  }
  if (config_.source_change_at && *config_.source_change_at == n) {
    config_.source_change_at.reset();
    change_source_locked(config_.source_change_to.first, config_.source_change_to.second);
  }
  if (auto it = config_.skip_before.find(n); it != config_.skip_before.end()) {
    sequence_ += it->second;
  }
  const uint32_t idx = incoming_.front();
  incoming_.pop_front();
  Buffer& buf = buffers_[idx];
  std::size_t used = 0;
  const bool fits = std::size_t(format_.bytesperline) * format_.height <= buf.memory.size();
  if (format_.pixelformat == V4L2_PIX_FMT_YUYV && !fits) {
    used = 0;  // a frame larger than the buffer: the driver can only flag it
  } else if (format_.pixelformat == V4L2_PIX_FMT_YUYV) {
    const uint32_t bpl = format_.bytesperline;
    for (uint32_t y = 0; y < format_.height; ++y) {
      for (uint32_t x = 0; x < bpl; ++x) {
        buf.memory[std::size_t(y) * bpl + x] =
            x < format_.width * 2 ? fake_yuyv_byte(sequence_, x, y) : 0xEE;
      }
    }
    used = std::size_t(bpl) * format_.height;
  } else if (!config_.mjpeg_frames.empty()) {
    const auto& jpeg = config_.mjpeg_frames[n % config_.mjpeg_frames.size()];
    used = std::min(jpeg.size(), buf.memory.size());
    std::memcpy(buf.memory.data(), jpeg.data(), used);
  }
  if (config_.truncate_at.count(n) != 0) used /= 3;

  v4l2_buffer& info = buf.info;
  info.bytesused = static_cast<uint32_t>(used);
  info.sequence = sequence_++;
  info.field = V4L2_FIELD_NONE;
  info.flags = config_.monotonic_timestamps
                   ? (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE)
                   : V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN;
  if (config_.error_at.count(n) != 0 || (format_.pixelformat == V4L2_PIX_FMT_YUYV && !fits))
    info.flags |= V4L2_BUF_FLAG_ERROR;
  if (config_.monotonic_timestamps) {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    // Exposure started a millisecond before the frame completed.
    const int64_t ns = int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec - 1'000'000;
    info.timestamp.tv_sec = ns / 1'000'000'000;
    info.timestamp.tv_usec = (ns % 1'000'000'000) / 1000;
  } else {
    info.timestamp.tv_sec = 1000 + static_cast<time_t>(n);  // some other clock entirely
    info.timestamp.tv_usec = 0;
  }
  buf.queued = false;
  buf.done = true;
  done_.push_back(idx);
  ++produced_;
  return true;
}

int FakeV4l2Device::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  if (count != 1) return fail(EINVAL);
  pollfd& p = fds[0];
  p.revents = 0;
  int wait_us = 0;
  {
    std::lock_guard lock(mutex_);
    if (dead_fds_.count(p.fd) != 0) {
      if (config_.unplug_fails_poll) return fail(ENODEV);
      p.revents = POLLERR | POLLHUP;
      return 1;
    }
    if (fds_.count(p.fd) == 0) {
      p.revents = POLLNVAL;
      return 1;
    }
    const short pri = pending_locked(p);
    if (pri != 0) {
      p.revents = static_cast<short>(pri | (done_.empty() ? 0 : POLLIN));
      return 1;
    }
    if (!done_.empty()) {
      p.revents = POLLIN;
      return 1;
    }
    if (!streaming_) {
      p.revents = POLLERR;  // what V4L2 answers when no stream is running
      return 1;
    }
    if (config_.eagain_before.erase(produced_) == 1) {
      eagain_pending_ = true;  // woke up, but the buffer is not there (a spurious wake-up)
      p.revents = POLLIN;
      return 1;
    }
    const bool can_produce = !incoming_.empty() && !stalled_;
    wait_us = can_produce ? config_.frame_period_us : timeout_ms * 1000;
  }
  std::this_thread::sleep_for(std::chrono::microseconds(wait_us));
  std::lock_guard lock(mutex_);
  produce_locked();
  if (dead_fds_.count(p.fd) != 0) {
    if (config_.unplug_fails_poll) return fail(ENODEV);
    p.revents = POLLERR | POLLHUP;
    return 1;
  }
  p.revents = static_cast<short>(pending_locked(p) | (done_.empty() ? 0 : POLLIN));
  return p.revents != 0 ? 1 : 0;
}

short FakeV4l2Device::pending_locked(const pollfd& p) const {
  const auto it = pending_events_.find(p.fd);
  const bool pending = it != pending_events_.end() && !it->second.empty();
  return pending && (p.events & POLLPRI) != 0 ? POLLPRI : 0;
}

void* FakeV4l2Device::mmap(void* /*addr*/, std::size_t length, int /*prot*/, int /*flags*/, int fd,
                           off_t offset) {
  std::lock_guard lock(mutex_);
  if (fds_.count(fd) == 0) {
    errno = dead_fds_.count(fd) != 0 ? ENODEV : EBADF;
    return MAP_FAILED;
  }
  for (auto& b : buffers_) {
    if (b.info.m.offset == static_cast<uint32_t>(offset) && length <= b.memory.size() &&
        length > 0) {
      ++b.mapped;
      return b.memory.data();
    }
  }
  errno = EINVAL;
  return MAP_FAILED;
}

int FakeV4l2Device::munmap(void* addr, std::size_t /*length*/) {
  std::lock_guard lock(mutex_);
  for (auto& b : buffers_) {
    if (b.memory.data() == addr && b.mapped > 0) {
      --b.mapped;
      return 0;
    }
  }
  return fail(EINVAL);
}

void FakeV4l2Device::replug() {
  std::lock_guard lock(mutex_);
  unplugged_ = false;
  sequence_ = 0;
  const bool any_mapped =
      std::any_of(buffers_.begin(), buffers_.end(), [](const Buffer& b) { return b.mapped > 0; });
  if (!any_mapped) buffers_.clear();
}

void FakeV4l2Device::resume() {
  std::lock_guard lock(mutex_);
  stalled_ = false;
}

int FakeV4l2Device::open_fds() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(fds_.size() + dead_fds_.size());
}

int FakeV4l2Device::mapped_buffers() const {
  std::lock_guard lock(mutex_);
  int n = 0;
  for (const auto& b : buffers_) n += b.mapped;
  return n;
}

uint64_t FakeV4l2Device::frames_produced() const {
  std::lock_guard lock(mutex_);
  return produced_;
}

uint64_t FakeV4l2Device::events_raised() const {
  std::lock_guard lock(mutex_);
  return events_raised_;
}

uint64_t FakeV4l2Device::qbuf_calls() const {
  std::lock_guard lock(mutex_);
  return qbuf_calls_;
}

bool FakeV4l2Device::streaming() const {
  std::lock_guard lock(mutex_);
  return streaming_;
}

v4l2_pix_format FakeV4l2Device::last_requested_format() const {
  std::lock_guard lock(mutex_);
  return last_request_;
}

std::optional<std::pair<uint32_t, uint32_t>> FakeV4l2Device::last_timeperframe() const {
  std::lock_guard lock(mutex_);
  return timeperframe_;
}

}  // namespace hd::drivers::testing
