#pragma once
// The one error a bad configuration or scene file raises: it names the file, the line and column,
// and the field, so the person editing the file can go straight to the mistake.

#include <stdexcept>
#include <string>

namespace hd::config {

/// what() = "<file>:<line>:<col>: <field>: <why>". Line and column are 1-based; 0 means unknown
/// (e.g. a file that cannot be read), and then they are left out of what(). An empty field (a
/// syntax error, an unreadable file) is left out too.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, int line, int column, std::string field, std::string why)
      : std::runtime_error(format(file, line, column, field, why)),
        file_(std::move(file)),
        line_(line),
        column_(column),
        field_(std::move(field)),
        why_(std::move(why)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& field() const { return field_; }  ///< e.g. "cameras[1].intrinsics.fx"
  const std::string& why() const { return why_; }

 private:
  static std::string format(const std::string& file, int line, int column, const std::string& field,
                            const std::string& why) {
    std::string s = file;
    if (line > 0) {
      s += ':' + std::to_string(line);
      if (column > 0) s += ':' + std::to_string(column);
    }
    s += ": ";
    if (!field.empty()) s += field + ": ";
    s += why;
    return s;
  }

  std::string file_;
  int line_ = 0;
  int column_ = 0;
  std::string field_;
  std::string why_;
};

}  // namespace hd::config
