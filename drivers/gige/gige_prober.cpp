#include "drivers/gige/gige_prober.h"

#include <arv.h>

#include <string>

#include "drivers/gobject_ptr.h"

namespace hd::drivers {

std::vector<DeviceInfo> probe_gige_devices() {
  std::vector<DeviceInfo> out;
  arv_update_device_list();
  const unsigned n = arv_get_n_devices();
  for (unsigned i = 0; i < n; ++i) {
    const char* protocol = arv_get_device_protocol(i);
    if (protocol == nullptr || std::string(protocol) != "GigEVision") continue;
    const char* id = arv_get_device_id(i);
    if (id == nullptr) continue;
    DeviceInfo info;
    info.kind = "gige";
    info.id = id;
    const char* vendor = arv_get_device_vendor(i);
    const char* model = arv_get_device_model(i);
    const char* address = arv_get_device_address(i);
    info.description = std::string(vendor != nullptr ? vendor : "?") + " " +
                       (model != nullptr ? model : "?") + " at " +
                       (address != nullptr ? address : "?");
    // Opening takes the control channel for a moment: the only honest test of "openable"
    // (another application holding control is the usual reason it fails).
    GErrorHolder error;
    GObjectPtr<ArvDevice> device(arv_open_device(id, error.out()));
    info.openable = device != nullptr && !error;
    if (!info.openable) info.reason = error ? error.message() : "Aravis could not open it";
    out.push_back(std::move(info));
  }
  return out;
}

}  // namespace hd::drivers
