#pragma once
// One line of `hybrid-station devices`: shared by every driver's prober so the command can list
// v4l2, gige, hid and usb devices side by side without knowing their APIs.
#include <string>

namespace hd::drivers {

struct DeviceInfo {
  std::string kind;         // "v4l2", "gige", "hid", "usb"
  std::string id;           // stable id to pass back to the driver (path, serial, bus:addr)
  std::string description;  // human-readable model / product string
  bool openable = false;    // true when this process could open the device right now
  std::string reason;       // why it cannot be opened (empty when openable)
};

}  // namespace hd::drivers
