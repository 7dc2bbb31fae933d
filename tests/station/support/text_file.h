#pragma once
// Reading and editing the text files the program tests write and the station writes back
// (configs, CSV, JSON): whole-file reads and a checked one-place replacement.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hd::station::testing {

/// The whole file ("" when it cannot be read: the caller's assertion then names what is missing).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// `s` with the first `from` replaced by `to`; a `from` that is not there fails the test, so an
/// edit of a config template can never silently do nothing.
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

/// One CSV line's cells (a trailing comma gives a last empty cell).
inline std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace hd::station::testing
