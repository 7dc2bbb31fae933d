#pragma once
// The contact sheet's model tile: the newest model snapshot drawn from a camera's place, its
// reconstructed part tinted so it stands apart from the a-priori part.

#include <opencv2/core.hpp>
#include <string>

#include "core/pinhole.h"
#include "core/pose.h"
#include "station/model/model_snapshot.h"

namespace hd::station {

/// The snapshot seen through `eye` at `T_world_eye` (CPU rasteriser), BGR. Meshes from
/// `snapshot.prior_meshes` on (the stereo pairs' reconstruction) are drawn with their texture
/// blended half-way to magenta; the a-priori meshes as they are.
cv::Mat render_model_tile(const ModelSnapshot& snapshot, const core::Pinhole& eye,
                          const core::Pose& T_world_eye);

/// The tile's label: "model #update, reconstructed: magenta (N v)" (N: reconstructed vertices).
std::string model_tile_label(const ModelSnapshot& snapshot);

}  // namespace hd::station
