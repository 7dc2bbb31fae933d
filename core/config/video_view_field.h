#pragma once
// The `video_view` field of a camera in station.yaml and in scene files.

#include "core/config/yaml_fields.h"
#include "core/video_view.h"

namespace hd::config {

/// `video_view: plane | fitted-plane | model-depth`, plane when absent; anything else fails
/// naming the field, its line and the choices.
inline core::VideoView read_video_view(const YamlFields& f) {
  const std::string name = f.optional_string("video_view", "plane");
  if (auto v = core::parse_video_view(name)) return *v;
  f.fail("video_view", "'" + name + "'; expected plane, fitted-plane or model-depth");
}

}  // namespace hd::config
