// `hybrid-station devices`: one line per device the station could use, with its kind, the id to
// configure it by, what it is, and "ok" or why this user cannot open it.
#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "drivers/device_info.h"
#include "drivers/hid/hidapi_transport.h"
#include "drivers/usb/usb_id.h"
#include "drivers/usb/usb_watcher.h"
#include "station/app/command.h"

// The camera drivers land independently; list them when they are there.
#if __has_include("drivers/v4l2/v4l2_prober.h")
#include "drivers/v4l2/v4l2_prober.h"
#define HD_HAVE_V4L2_PROBER 1
#endif
#if __has_include("drivers/gige/gige_prober.h")
#include "drivers/gige/gige_prober.h"
#define HD_HAVE_GIGE_PROBER 1
#endif

namespace hd::station {
namespace {

struct DevicesOptions {
  std::vector<std::string> usb_ids;
  bool no_gige = false;
};

std::string pad(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : s + std::string(width - s.size(), ' ');
}

int run_devices(const DevicesOptions& opt) {
  std::vector<drivers::UsbId> usb_ids = drivers::known_usb_ids();
  for (const std::string& text : opt.usb_ids) {
    auto id = drivers::parse_usb_id(text);
    if (!id) {
      std::cerr << "hybrid-station devices: --usb-id \"" << text
                << "\" is not VID:PID in hex (e.g. 1532:0b00)\n";
      return 2;
    }
    id->label = "configured USB device";
    usb_ids.push_back(*id);
  }

  std::vector<drivers::DeviceInfo> all;
  const auto add = [&all](std::vector<drivers::DeviceInfo> more) {
    all.insert(all.end(), std::make_move_iterator(more.begin()),
               std::make_move_iterator(more.end()));
  };
#ifdef HD_HAVE_V4L2_PROBER
  add(drivers::probe_v4l2_devices());
#endif
#ifdef HD_HAVE_GIGE_PROBER
  if (!opt.no_gige) add(drivers::probe_gige_devices());
#endif
  add(drivers::probe_hid_devices());
  {
    drivers::UsbWatcher usb(usb_ids);
    if (!usb.available()) std::cerr << "# usb: " << usb.reason() << "\n";
  }
  add(drivers::probe_usb_devices(usb_ids));

  if (all.empty()) {
    std::cerr << "# no devices found (cameras: v4l2, gige; head trackers: hid; usb: ";
    for (std::size_t i = 0; i < usb_ids.size(); ++i)
      std::cerr << (i ? ", " : "")
                << drivers::to_string(usb_ids[i].vendor_id, usb_ids[i].product_id);
    std::cerr << ")\n";
    return 0;
  }
  std::size_t id_width = 0;
  for (const auto& d : all) id_width = std::max(id_width, d.id.size());
  for (const auto& d : all) {
    std::cout << pad(d.kind, 4) << "  " << pad(d.id, id_width) << "  (" << d.description << ")  "
              << (d.openable ? std::string("ok") : "cannot open: " + d.reason) << "\n";
  }
  return 0;
}

const CommandRegistrar registrar{[](CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<DevicesOptions>();
  CLI::App* cmd = app.add_subcommand(
      "devices", "List cameras (v4l2, gige), head trackers (hid) and watched USB devices");
  cmd->add_option("--usb-id", opt->usb_ids, "Also list this USB VID:PID (hex), repeatable");
  cmd->add_flag("--no-gige", opt->no_gige, "Skip GigE discovery (it takes about a second)");
  cmd->callback([opt, &exit_code] { exit_code = run_devices(*opt); });
}};

}  // namespace
}  // namespace hd::station
