// `hybrid-station run`: the command line. The work is in station_run.cpp.
#include <memory>

#include "station/app/command.h"
#include "station/app/run_options.h"
#include "station/app/station_run.h"

namespace hd::station {
namespace {

const CommandRegistrar kRegister{[](CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Run the station's fixed-rate loop on a simulated scene (--scene, default "
      "scenes/default.yaml) or on real devices (--config station.yaml).\n"
      "Examples:\n"
      "  hybrid-station run --headless --out out/demo\n"
      "  hybrid-station run --scene scenes/default.yaml --headless --seconds 20 --video "
      "out/demo/run.avi --out out/demo\n"
      "  hybrid-station run --config station.yaml            (window; R re-centres, Esc quits)\n"
      "Writes DIR/latency.csv, latency.png, frames.csv (m, w_video, camera, variant per frame),\n"
      "trace.png (m and w_video over time), contact_sheet.png and summary.json.\n"
      "Exit codes: 0 done, 1 runtime failure, 2 bad scene/config file (file:line:col: field),\n"
      "3 a required device is missing (or a camera cannot deliver its calibrated size).");
  add_run_options(*cmd, *opts);
  cmd->callback([opts, &exit_code] { exit_code = run_station(*opts); });
}};

}  // namespace
}  // namespace hd::station
