#pragma once
// The pictures of a replay camera id, read with the calibration images' reader: what the programs
// pass to drivers::make_camera_source so that "replay:DIR/GLOB" ids play image files.

#include <vector>

#include "drivers/camera_factory.h"
#include "drivers/replay/replay_camera.h"

namespace hd::calib {

/// The images of `id.folder` matching `id.pattern`, sorted by name, as 8-bit gray with rows packed
/// (load_image_set: throws InputError naming the folder or the bad file, or two sizes that
/// differ). Fits drivers::ReplayImageLoader.
std::vector<drivers::ReplayImage> load_replay_images(const drivers::ReplayId& id);

}  // namespace hd::calib
