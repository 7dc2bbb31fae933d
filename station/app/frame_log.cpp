#include "station/app/frame_log.h"

#include <algorithm>

namespace hd::station {

// Value-initialising every row touches its pages now, not one by one during the run (a soak
// would otherwise see resident memory creep up at the logging rate).
FrameLog::FrameLog(std::size_t capacity) : rows_(std::max<std::size_t>(capacity, 1)) {}

}  // namespace hd::station
