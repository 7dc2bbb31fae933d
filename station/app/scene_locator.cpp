#include "station/app/scene_locator.h"

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

}  // namespace hd::station
