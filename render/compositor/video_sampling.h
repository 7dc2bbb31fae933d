#pragma once
// How the video frame is sampled when it is warped into the eye's view.

#include <cstdint>

namespace hd::render {

/// kBilinear is the product's choice; kNearest exists so the benchmark can print what it costs.
enum class VideoSampling : uint8_t { kBilinear, kNearest };

}  // namespace hd::render
