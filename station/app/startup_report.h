#pragma once
// What the station found at start and what it uses: every device with its status, or the
// reason it is missing.

#include <cstdio>
#include <string>
#include <vector>

namespace hd::station {

enum class DeviceStatus {
  kOpened,   ///< found and opened; `detail` says what it uses
  kMissing,  ///< required and not usable: the run stops; `detail` is the reason
  kSkipped,  ///< optional and not usable: the run goes on without it; `detail` is the reason
};

struct DeviceLine {
  std::string role;  ///< "camera", "tracker", "display", "model", ...
  std::string id;
  DeviceStatus status = DeviceStatus::kOpened;
  std::string detail;
};

class StartupReport {
 public:
  void opened(std::string role, std::string id, std::string detail);
  /// Required: the run cannot go on. Optional: recorded as skipped.
  void missing(std::string role, std::string id, std::string reason, bool optional);
  /// A line about the run itself (scene file, parameters), printed after the devices.
  void note(std::string key, std::string value);

  bool fatal() const;
  const std::vector<DeviceLine>& devices() const { return devices_; }
  /// "camera sim:left: <reason>; tracker hid: <reason>" for every required missing device.
  std::string missing_summary() const;
  void print(std::FILE* out) const;

 private:
  std::vector<DeviceLine> devices_;
  std::vector<std::pair<std::string, std::string>> notes_;
};

}  // namespace hd::station
