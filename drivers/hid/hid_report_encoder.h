#pragma once
// The inverse of the parser: writes a byte-exact input report for a format. Used by the mock
// head tracker (so the real parser runs end to end) and by the fuzzer to seed valid reports.
// Never emits -32768: values saturate at +-32767.

#include <cstddef>
#include <cstdint>
#include <span>

#include "drivers/hid/hid_report_format.h"
#include "drivers/hid/hid_report_parser.h"

namespace hd::drivers {

/// Writes `format.input_length_bytes` bytes into `out` (which must be at least that long) and
/// returns that length, or 0 when `out` is too short. Unused bytes are zero.
std::size_t encode_hid_report(const HidReportFormat& format, const HidSample& sample,
                              std::span<uint8_t> out);

/// The control feature report (id + one byte) that starts streaming at `interval_ms`
/// (`enable` = false writes the "no events, power off" byte that stops it).
std::size_t encode_control_feature(const HidReportFormat& format, bool enable, int interval_ms,
                                   std::span<uint8_t> out);

}  // namespace hd::drivers
