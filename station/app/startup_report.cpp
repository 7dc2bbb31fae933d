#include "station/app/startup_report.h"

#include <algorithm>

namespace hd::station {

void StartupReport::opened(std::string role, std::string id, std::string detail) {
  devices_.push_back({std::move(role), std::move(id), DeviceStatus::kOpened, std::move(detail)});
}

void StartupReport::missing(std::string role, std::string id, std::string reason, bool optional) {
  devices_.push_back({std::move(role), std::move(id),
                      optional ? DeviceStatus::kSkipped : DeviceStatus::kMissing,
                      std::move(reason)});
}

void StartupReport::note(std::string key, std::string value) {
  notes_.emplace_back(std::move(key), std::move(value));
}

bool StartupReport::fatal() const {
  return std::any_of(devices_.begin(), devices_.end(),
                     [](const DeviceLine& d) { return d.status == DeviceStatus::kMissing; });
}

std::string StartupReport::missing_summary() const {
  std::string s;
  for (const DeviceLine& d : devices_) {
    if (d.status != DeviceStatus::kMissing) continue;
    if (!s.empty()) s += "; ";
    s += d.role + " " + d.id + ": " + d.detail;
  }
  return s;
}

void StartupReport::print(std::FILE* out) const {
  for (const DeviceLine& d : devices_) {
    const char* status = d.status == DeviceStatus::kOpened    ? "ok     "
                         : d.status == DeviceStatus::kMissing ? "MISSING"
                                                              : "skipped";
    std::fprintf(out, "  %-8s %s %s: %s\n", d.role.c_str(), status, d.id.c_str(), d.detail.c_str());
  }
  for (const auto& [key, value] : notes_)
    std::fprintf(out, "  %-16s %s\n", (key + ":").c_str(), value.c_str());
  std::fflush(out);
}

}  // namespace hd::station
