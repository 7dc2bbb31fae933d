// hybrid-calib: camera intrinsics p_c and pose P_c from checkerboard views.
#include <spdlog/spdlog.h>

#include "calib/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"hybrid-calib: estimate a camera's intrinsics and workspace pose from chessboards"};
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  hybrid-calib intrinsics --images data/calib/opencv-left --pattern 'left*' --board 9x6 \\\n"
      "      --square 0.025 --fix-aspect --out left.yml --report left.png --ros left_ros.yaml\n"
      "  hybrid-calib pose --intrinsics left.yml --image board_on_table.jpg --board 7x7 \\\n"
      "      --square 0.0195 --board-pose 0.5,0,0.8,0,0,0 --expect-camera-dir 0,-1,1 --out "
      "cam0.yml");
  int exit_code = 0;
  hd::calib::add_intrinsics_command(app, exit_code);
  hd::calib::add_pose_command(app, exit_code);
  hd::calib::add_stereo_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : hd::calib::kBadInput;
  }
  return exit_code;
}
