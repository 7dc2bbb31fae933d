#pragma once
// `hybrid-station run`: load the scene or station config, assemble and report the devices, run
// the fixed-rate loop, write the outputs.

#include "station/app/run_options.h"

namespace hd::station {

/// Exit codes: 0 done; 1 a runtime failure (message on stderr); 2 a bad scene/config file
/// ("<file>:<line>:<col>: <field>: <why>"); 3 a required device is missing (each named with its
/// reason).
int run_station(const RunOptions& options);

}  // namespace hd::station
