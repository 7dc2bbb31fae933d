#include "drivers/v4l2/v4l2_mode.h"

#include <linux/videodev2.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace hd::drivers {

bool v4l2_fourcc_supported(uint32_t fourcc) {
  return fourcc == V4L2_PIX_FMT_YUYV || fourcc == V4L2_PIX_FMT_MJPEG || fourcc == V4L2_PIX_FMT_JPEG;
}

PixelFormat v4l2_pixel_format(uint32_t fourcc) {
  return fourcc == V4L2_PIX_FMT_YUYV ? PixelFormat::kYuyv : PixelFormat::kMjpeg;
}

std::string v4l2_fourcc_name(uint32_t fourcc) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xFF);
    s[i] = (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

std::optional<V4l2ModeChoice> choose_v4l2_mode(const std::vector<V4l2Mode>& modes,
                                               const V4l2ModeRequest& request) {
  using Key = std::tuple<int, double, int, double, int>;
  std::optional<V4l2ModeChoice> best;
  Key best_key{};
  const double req_area = double(request.width_px) * double(request.height_px);
  for (const V4l2Mode& m : modes) {
    if (!v4l2_fourcc_supported(m.fourcc) || m.width_px <= 0 || m.height_px <= 0) continue;
    if (request.fourcc != 0 && m.fourcc != request.fourcc) continue;
    const double area = double(m.width_px) * double(m.height_px);
    int size_class = 2;
    double size_cost = -area;  // among smaller sizes, the largest
    if (m.width_px == request.width_px && m.height_px == request.height_px) {
      size_class = 0;
      size_cost = 0;
    } else if (m.width_px >= request.width_px && m.height_px >= request.height_px) {
      size_class = 1;
      size_cost = area - req_area;
    }
    const int format_rank = m.fourcc == V4L2_PIX_FMT_YUYV ? 0 : 1;
    std::vector<V4l2Interval> intervals = m.intervals;
    if (intervals.empty()) intervals.push_back({});
    for (const V4l2Interval& iv : intervals) {
      const double fps = iv.fps();
      // An unlisted rate (0) ranks below any listed rate that reaches the request.
      const int rate_class = (fps > 0 && fps + 1e-6 >= request.fps) ? 0 : 1;
      const double rate_cost = fps > 0 ? std::abs(fps - request.fps) : 1e9;
      const Key key{size_class, size_cost, rate_class, rate_cost, format_rank};
      if (!best || key < best_key) {
        best = V4l2ModeChoice{m.fourcc, m.width_px, m.height_px, iv};
        best_key = key;
      }
    }
  }
  return best;
}

namespace {

int snap(int want, uint32_t lo, uint32_t hi, uint32_t step) {
  const int64_t clamped = std::clamp<int64_t>(want, lo, hi);
  if (step <= 1) return static_cast<int>(clamped);
  return static_cast<int>(lo + (clamped - lo) / step * step);
}

std::vector<V4l2Interval> enumerate_intervals(V4l2Syscalls& sys, int fd, uint32_t fourcc, int w,
                                              int h) {
  std::vector<V4l2Interval> out;
  for (uint32_t i = 0; i < 64; ++i) {  // bounded: a broken driver cannot loop us forever
    v4l2_frmivalenum e{};
    e.index = i;
    e.pixel_format = fourcc;
    e.width = static_cast<uint32_t>(w);
    e.height = static_cast<uint32_t>(h);
    if (sys.ioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &e) != 0) break;
    if (e.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
      if (e.discrete.numerator != 0 && e.discrete.denominator != 0) {
        out.push_back({e.discrete.numerator, e.discrete.denominator});
      }
    } else {
      out.push_back({e.stepwise.min.numerator, e.stepwise.min.denominator});
      out.push_back({e.stepwise.max.numerator, e.stepwise.max.denominator});
      break;
    }
  }
  return out;
}

}  // namespace

std::vector<V4l2Mode> enumerate_v4l2_modes(V4l2Syscalls& sys, int fd,
                                           const V4l2ModeRequest& request) {
  std::vector<V4l2Mode> modes;
  for (uint32_t fi = 0; fi < 64; ++fi) {
    v4l2_fmtdesc fmt{};
    fmt.index = fi;
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (sys.ioctl(fd, VIDIOC_ENUM_FMT, &fmt) != 0) break;
    for (uint32_t si = 0; si < 256; ++si) {
      v4l2_frmsizeenum size{};
      size.index = si;
      size.pixel_format = fmt.pixelformat;
      if (sys.ioctl(fd, VIDIOC_ENUM_FRAMESIZES, &size) != 0) break;
      V4l2Mode mode;
      mode.fourcc = fmt.pixelformat;
      if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
        mode.width_px = static_cast<int>(size.discrete.width);
        mode.height_px = static_cast<int>(size.discrete.height);
      } else {
        const auto& s = size.stepwise;
        mode.width_px = snap(request.width_px, s.min_width, s.max_width, s.step_width);
        mode.height_px = snap(request.height_px, s.min_height, s.max_height, s.step_height);
      }
      mode.intervals = enumerate_intervals(sys, fd, mode.fourcc, mode.width_px, mode.height_px);
      modes.push_back(std::move(mode));
      if (size.type != V4L2_FRMSIZE_TYPE_DISCRETE) break;
    }
  }
  return modes;
}

}  // namespace hd::drivers
