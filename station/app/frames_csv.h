#pragma once
// frames.csv: one row per displayed frame with what the station decided.

#include <string>
#include <vector>

#include "station/app/frame_log.h"

namespace hd::station {

/// Columns: frame, t_s, m ("inf" when no camera is usable), w_video (9 decimals: a hybrid frame
/// never prints as 1 or 0), camera (index, -1 none),
/// camera_name, variant (video|hybrid|synthetic), missed_deadline (0|1), guidance (0|1),
/// guidance_distance_m, guidance_dir_x, guidance_dir_y, head_x_m, head_y_m, head_z_m.
/// Written to a temp file and renamed; throws std::runtime_error naming the file on failure.
void write_frames_csv(const FrameLog& log, const std::vector<std::string>& camera_names,
                      const std::string& path);

const char* variant_name(core::Variant v);

}  // namespace hd::station
