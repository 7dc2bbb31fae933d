#pragma once
// Lists V4L2 capture nodes for `hybrid-station devices`.

#include <filesystem>
#include <vector>

#include "drivers/device_info.h"
#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers {

/// Every /dev/video* node, in numeric order: its card name, driver, bus and convertible formats,
/// or why it cannot be used (permission -> the udev rules / `video` group; a metadata node; busy).
/// Returns an empty list when there are no nodes.
std::vector<DeviceInfo> probe_v4l2_devices();

/// The same over another directory and syscall seam (tests).
std::vector<DeviceInfo> probe_v4l2_devices(V4l2Syscalls& sys, const std::filesystem::path& dev_dir);

}  // namespace hd::drivers
