#pragma once
// One published state of the synthetic model, as the station draws it.

#include <cstdint>

#include "render/compositor/synthetic_scene.h"

namespace hd::station {

/// The model plus when its textures were seen. `scene.revision` increases with every publish.
/// Times are CLOCK_MONOTONIC ns (the stamps of the camera frames used); 0 = the a-priori model,
/// no camera frame in it yet.
struct ModelSnapshot {
  render::SyntheticScene scene;
  int64_t capture_oldest_ns = 0;  ///< the oldest frame the textures came from: the model's age
  int64_t capture_newest_ns = 0;
  int64_t taken_ns = 0;      ///< when the updater took the frames (its clock)
  int64_t published_ns = 0;  ///< when this snapshot was published (its clock)
  uint64_t update = 0;       ///< 1 for the first update, 0 for the a-priori model
  /// scene.meshes[0, prior_meshes) are the a-priori model; the meshes after them are the stereo
  /// pairs' reconstruction (one per pair, empty = nothing new seen), as the contact sheet tints.
  std::size_t prior_meshes = 0;
  int64_t reconstruct_ns = 0;    ///< what the reconstruction of this update took (0: none)
  int64_t reconstructed_ns = 0;  ///< when that reconstruction ended (its clock; 0: none)
};

}  // namespace hd::station
