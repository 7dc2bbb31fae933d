#pragma once
// Reads an HMD profile from a YAML file or node, checked (format: docs/hmd.md).

#include <stdexcept>
#include <string>

#include "render/lens/hmd_profile.h"

namespace YAML {
class Node;
}

namespace hd::render::lens {

/// what() = "<file>:<line>:<col>: <field>: <why>" (line and column left out when unknown); the
/// why names the value found.
class HmdProfileError : public std::runtime_error {
 public:
  HmdProfileError(const std::string& file, int line, int column, std::string field,
                  const std::string& why);
  const std::string& field() const { return field_; }
  const std::string& why() const { return why_; }
  int line() const { return line_; }
  int column() const { return column_; }

 private:
  std::string field_;
  std::string why_;
  int line_ = 0;
  int column_ = 0;
};

/// Reads and checks (check_profile) a profile file; any mistake -- unreadable file, YAML
/// syntax, unknown or missing key, wrong type, a value check_profile refuses -- throws
/// HmdProfileError naming the file, the field and the value.
HmdProfile load_hmd_profile(const std::string& path);

/// The same from a node (an inline profile in a station file); `file` names it in messages.
HmdProfile read_hmd_profile(const YAML::Node& node, const std::string& file);

/// A profile by name ("oculus-dk1") from the shipped profiles (render/lens/profiles/ of the
/// source tree this program was built from), or by path when `name_or_path` names a file
/// (relative paths against `base_dir`). Throws HmdProfileError listing the shipped names when
/// there is no such profile.
HmdProfile find_hmd_profile(const std::string& name_or_path, const std::string& base_dir);

/// Where the shipped profiles are.
std::string shipped_profile_dir();

}  // namespace hd::render::lens
