#pragma once
// Reads an HMD profile from a YAML file or node, checked (format: docs/hmd.md), through the
// shared config reader (core/config/yaml_fields.h): a mistake is a config::ConfigError,
// "<file>:<line>:<col>: <field>: <why>", as in scene files and station.yaml.

#include <string>

#include "core/config/config_error.h"
#include "core/config/yaml_fields.h"
#include "render/lens/hmd_profile.h"

namespace hd::render::lens {

/// Reads and checks (check_profile) a profile file; any mistake -- unreadable file, YAML
/// syntax, unknown or missing key, wrong type, a value check_profile refuses -- throws
/// config::ConfigError naming the file, the line, the field and the value.
HmdProfile load_hmd_profile(const std::string& path);

/// The same from a node (an inline profile in a station file); `file` names it in messages.
HmdProfile read_hmd_profile(const YAML::Node& node, const std::string& file);

/// The same from a node of a larger file: the node's field path prefixes every field in messages
/// ("display.hmd.fov_deg[0]").
HmdProfile read_hmd_profile(const config::YamlFields& node);

/// A profile by name ("oculus-dk1") from the shipped profiles (render/lens/profiles/ of the
/// source tree this program was built from), or by path when `name_or_path` names a file
/// (relative paths against `base_dir`). Throws config::ConfigError listing the shipped names when
/// there is no such profile.
HmdProfile find_hmd_profile(const std::string& name_or_path, const std::string& base_dir);

/// Where the shipped profiles are.
std::string shipped_profile_dir();

}  // namespace hd::render::lens
