#include "sim/scene_epoch.h"

#include <time.h>

#include <cctype>

namespace hd::sim {

std::optional<int64_t> parse_scene_epoch(const std::string& text, std::string& why) {
  std::size_t i = 0;
  int64_t seconds = 0;
  int digits = 0;
  for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i, ++digits) {
    if (digits >= 12) {
      why = "'" + text + "': too many digits for seconds since 1970";
      return std::nullopt;
    }
    seconds = seconds * 10 + (text[i] - '0');
  }
  if (digits == 0) {
    why = "'" + text + "': expected seconds since 1970 on CLOCK_REALTIME, e.g. $(date +%s.%N)";
    return std::nullopt;
  }
  int64_t fraction_ns = 0;
  if (i < text.size() && text[i] == '.') {
    int64_t scale = 100'000'000;
    for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i) {
      if (scale == 0) {
        why = "'" + text + "': more than nine decimals (ns)";
        return std::nullopt;
      }
      fraction_ns += (text[i] - '0') * scale;
      scale /= 10;
    }
  }
  if (i != text.size()) {
    why = "'" + text + "': unexpected '" + text.substr(i) + "' (seconds since 1970, e.g. " +
          "1764650000.25)";
    return std::nullopt;
  }
  return seconds * 1'000'000'000 + fraction_ns;
}

int64_t realtime_to_monotonic_ns(int64_t realtime_ns) {
  timespec r{}, m{};
  ::clock_gettime(CLOCK_REALTIME, &r);
  ::clock_gettime(CLOCK_MONOTONIC, &m);
  const int64_t offset_ns = (int64_t{r.tv_sec} - int64_t{m.tv_sec}) * 1'000'000'000 +
                            (int64_t{r.tv_nsec} - int64_t{m.tv_nsec});
  return realtime_ns - offset_ns;
}

}  // namespace hd::sim
