#pragma once
// printf-style text for the start report and the summary: a format and up to four numbers.

#include <cstdio>
#include <string>

namespace hd::station {

/// `f` (printf conversions for doubles, e.g. "%.1f ms") with up to four numbers; the result is cut
/// at 159 characters, far beyond any report line's figures.
inline std::string fmt(const char* f, double a = 0, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

}  // namespace hd::station
