#pragma once
// Output files appear whole or not at all.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace hd::calib {

class OutputExists : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes `content` to a temp file beside `path`, fsyncs it and renames it over `path`. If `path`
/// exists: without `force` throws OutputExists (nothing written); with `force` the old file is
/// kept as `path + ".bak"`. Throws std::runtime_error naming the file on any I/O failure, after
/// removing the temp file.
void write_file_atomically(const std::filesystem::path& path, const std::string& content,
                           bool force);

/// Throws OutputExists unless `force` or `path` is absent; lets a command refuse before it spends
/// minutes calibrating.
void check_output_free(const std::filesystem::path& path, bool force);

}  // namespace hd::calib
