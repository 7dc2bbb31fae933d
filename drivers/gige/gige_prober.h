#pragma once
// Lists the GigE Vision cameras reachable from this host for `hybrid-station devices`.

#include <vector>

#include "drivers/device_info.h"

namespace hd::drivers {

/// Runs Aravis discovery (a GVCP broadcast on every interface, loopback included; about 1 s)
/// and reports each GigE Vision device with kind "gige", its Aravis id (the id GigeCamera opens)
/// and whether this process could take control of it now; if not, Aravis's reason.
std::vector<DeviceInfo> probe_gige_devices();

}  // namespace hd::drivers
