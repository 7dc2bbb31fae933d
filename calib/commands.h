#pragma once
// hybrid-calib's subcommands; each file adds one to the CLI app.

#include <CLI/CLI.hpp>

namespace hd::calib {

/// Exit codes: 0 ok, 1 calibration failed (no board, too few views, refused pose),
/// 2 bad input (options, files, images), 3 output exists (no --force), 4 I/O error writing.
enum ExitCode { kOk = 0, kFailed = 1, kBadInput = 2, kOutputExists = 3, kWriteError = 4 };

void add_intrinsics_command(CLI::App& app, int& exit_code);
void add_pose_command(CLI::App& app, int& exit_code);
void add_stereo_command(CLI::App& app, int& exit_code);

}  // namespace hd::calib
