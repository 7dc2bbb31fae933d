#pragma once
// Where the default scene is when no --scene or --config is given.

#include <string>

namespace hd::station {

struct LocatedFile {
  std::string path;
  std::string how;  ///< "current directory" or "source tree <dir>"
};

/// `scenes/default.yaml` in the current directory, else in the source tree this program was built
/// from. Throws std::runtime_error naming both places when neither has it.
LocatedFile locate_default_scene();

/// `given` when not empty, else the default scene; prints which, after "`program`: " (the start
/// report's first line).
std::string scene_or_default(const std::string& given, const std::string& program,
                             const std::string& no_option_text);

}  // namespace hd::station
