#pragma once
// Reading a scene file (YAML; format in docs/scenes.md) into a Scene.

#include <string>

#include "core/config/config_error.h"
#include "core/config/yaml_fields.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// Reads and checks `path`. Any mistake -- YAML syntax, a missing or unknown key (with a "did you
/// mean"), a wrong type, a value out of range, an unknown effect, a missing calibration, trajectory
/// or texture file -- throws config::ConfigError naming the file, line and field.
Scene load_scene(const std::string& path);

/// The same from text; `name` stands for the file in messages and relative paths resolve against
/// its directory.
Scene parse_scene(const std::string& text, const std::string& name);

/// One `stereo:` item (scene files and station.yaml's `model.stereo`): left and right must be
/// two different names of `camera_names`. config::ConfigError naming the field otherwise.
SceneStereoPair read_stereo_pair(const config::YamlFields& item,
                                 const std::vector<std::string>& camera_names);

}  // namespace hd::sim
