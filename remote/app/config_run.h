#pragma once
// hybrid-remote --config remote.yaml: the site's real cameras through drivers/ to the station.

#include <atomic>
#include <string>

namespace hd::remote {

/// Opens every camera of `config_file` (each asked for its calibration's size, which it must
/// deliver), chooses the H.264 encoder, prints the start report (cameras found, encoder and why,
/// destinations, calibration, security), streams until `stop` or `seconds` (> 0), prints the
/// counts. Returns the exit code: 0 done, 2 a bad config file (file:line:col: field: why), 3 a
/// camera or encoder that cannot be used.
int run_config(const std::string& config_file, double seconds, const std::atomic<bool>& stop);

}  // namespace hd::remote
