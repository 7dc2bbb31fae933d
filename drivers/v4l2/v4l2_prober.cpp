#include "drivers/v4l2/v4l2_prober.h"

#include <fcntl.h>
#include <linux/videodev2.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "drivers/v4l2/unique_fd.h"
#include "drivers/v4l2/v4l2_mode.h"

namespace hd::drivers {
namespace {

std::string bounded(const uint8_t* s, std::size_t n) {
  const auto* c = reinterpret_cast<const char*>(s);
  return std::string(c, strnlen(c, n));
}

// "video12" -> 12; anything else -> -1.
long node_number(const std::string& name) {
  if (name.rfind("video", 0) != 0 || name.size() == 5 || name.size() > 12) return -1;
  long n = 0;
  for (std::size_t i = 5; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return -1;
    n = n * 10 + (name[i] - '0');
  }
  return n;
}

DeviceInfo probe_node(V4l2Syscalls& sys, const std::string& path) {
  DeviceInfo info;
  info.kind = "v4l2";
  info.id = path;
  const int raw = sys.open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (raw < 0) {
    const int err = errno;
    if (err == EACCES || err == EPERM) {
      info.reason =
          "permission denied: install udev/70-hybrid-station.rules (then `sudo udevadm "
          "control --reload && sudo udevadm trigger`) or add the user to the 'video' "
          "group and log in again";
    } else if (err == EBUSY) {
      info.reason = "busy: another program has it open";
    } else {
      info.reason = "cannot open: " + std::error_code(err, std::generic_category()).message();
    }
    return info;
  }
  UniqueFd fd(sys, raw);
  v4l2_capability cap{};
  if (sys.ioctl(fd.get(), VIDIOC_QUERYCAP, &cap) != 0) {
    info.reason = "not a V4L2 device (VIDIOC_QUERYCAP failed)";
    return info;
  }
  info.description = bounded(cap.card, sizeof(cap.card)) + " (" +
                     bounded(cap.driver, sizeof(cap.driver)) + ", " +
                     bounded(cap.bus_info, sizeof(cap.bus_info)) + ")";
  const uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0) {
    info.reason = "not a video capture node (UVC cameras also expose a metadata node)";
    return info;
  }
  if ((caps & V4L2_CAP_STREAMING) == 0) {
    info.reason = "no streaming I/O";
    return info;
  }
  std::string formats;
  for (uint32_t i = 0; i < 64; ++i) {
    v4l2_fmtdesc f{};
    f.index = i;
    f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (sys.ioctl(fd.get(), VIDIOC_ENUM_FMT, &f) != 0) break;
    if (v4l2_fourcc_supported(f.pixelformat)) formats += " " + v4l2_fourcc_name(f.pixelformat);
  }
  if (formats.empty()) {
    info.reason = "offers neither YUYV nor MJPEG";
    return info;
  }
  info.description += ";" + formats;
  info.openable = true;
  return info;
}

}  // namespace

std::vector<DeviceInfo> probe_v4l2_devices(V4l2Syscalls& sys,
                                           const std::filesystem::path& dev_dir) {
  std::vector<std::pair<long, std::string>> nodes;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dev_dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    const long n = node_number(it->path().filename().string());
    if (n >= 0) nodes.emplace_back(n, it->path().string());
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<DeviceInfo> out;
  out.reserve(nodes.size());
  for (const auto& [n, path] : nodes) out.push_back(probe_node(sys, path));
  return out;
}

std::vector<DeviceInfo> probe_v4l2_devices() {
  return probe_v4l2_devices(libc_v4l2_syscalls(), "/dev");
}

}  // namespace hd::drivers
