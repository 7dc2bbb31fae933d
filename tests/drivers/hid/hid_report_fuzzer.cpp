// libFuzzer entry (clang only): the first byte picks the format, the rest is the report.
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "drivers/hid/hid_report_parser.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  static const hd::drivers::HidReportFormat formats[] = {hd::drivers::android_head_tracker_v1(),
                                                         hd::drivers::osvr_hdk()};
  if (size == 0) return 0;
  const auto& f = formats[data[0] & 1];
  const auto res = hd::drivers::parse_hid_report(f, std::span<const uint8_t>(data + 1, size - 1));
  if (res.ok && !(std::fabs(res.sample.q_tracker_head.norm() - 1.0) < 1e-9)) __builtin_trap();
  return 0;
}
