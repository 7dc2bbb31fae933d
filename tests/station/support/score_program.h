#pragma once
// Running the built `hybrid-station score` from a test and reading its score.csv by column name,
// so a test says `cell(row, "psnr_video_db")` instead of counting commas.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/text_file.h"
#include "test_paths.h"

namespace hd::station::testing {

/// Runs `hybrid-station score ARGS` in the source tree (so relative scene names resolve as for a
/// user), stdout and stderr into `log`; the exit code (-1: killed by a signal).
inline int run_score_program(const std::string& args, const std::filesystem::path& log) {
  const std::string cmd = "cd '" + std::string(hd::test::source_dir()) + "' && '" +
                          std::string(hd::test::station_bin()) + "' score " + args + " > '" +
                          log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// One row of score.csv: column name -> cell text.
using ScoreCsvRow = std::map<std::string, std::string>;

/// Every data row of a score.csv (empty when the file cannot be read: the caller asserts on it).
inline std::vector<ScoreCsvRow> read_score_csv(const std::filesystem::path& p) {
  std::stringstream s(slurp(p));
  std::string line;
  std::vector<ScoreCsvRow> rows;
  if (!std::getline(s, line)) return rows;
  const std::vector<std::string> header = split_csv_line(line);
  while (std::getline(s, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    EXPECT_EQ(cells.size(), header.size()) << line;
    ScoreCsvRow row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

/// A numeric cell; NaN when empty (score.csv leaves a score empty when there was nothing to
/// score, e.g. no video pixel). A missing column fails the test.
inline double cell(const ScoreCsvRow& row, const std::string& column) {
  const auto it = row.find(column);
  EXPECT_NE(it, row.end()) << "no column " << column;
  if (it == row.end() || it->second.empty()) return NAN;
  return std::stod(it->second);
}

}  // namespace hd::station::testing
