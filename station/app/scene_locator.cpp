#include "station/app/scene_locator.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#ifndef HD_SOURCE_DIR
#define HD_SOURCE_DIR ""
#endif

namespace hd::station {

LocatedFile locate_default_scene() {
  namespace fs = std::filesystem;
  const fs::path relative = fs::path("scenes") / "default.yaml";
  std::error_code ec;
  if (fs::is_regular_file(relative, ec)) return {relative.string(), "current directory"};
  const fs::path source_tree = HD_SOURCE_DIR;
  if (!source_tree.empty() && fs::is_regular_file(source_tree / relative, ec))
    return {(source_tree / relative).string(), "source tree " + source_tree.string()};
  throw std::runtime_error("no --scene or --config given and no default scene: neither " +
                           (fs::current_path(ec) / relative).string() + " nor " +
                           (source_tree / relative).string() + " exists");
}

std::string scene_or_default(const std::string& given, const std::string& program,
                             const std::string& no_option_text) {
  if (!given.empty()) {
    std::printf("%s: scene %s (simulated devices)\n", program.c_str(), given.c_str());
    return given;
  }
  const LocatedFile f = locate_default_scene();
  std::printf("%s: %s: default scene %s (found in the %s)\n", program.c_str(),
              no_option_text.c_str(), f.path.c_str(), f.how.c_str());
  return f.path;
}

}  // namespace hd::station
