#pragma once
// What a consumer (the render loop) sees while polling a network camera's mailbox: the frames
// shown, and any presented as new that was not newer than the last (old video as new: must be 0).

#include <algorithm>
#include <cstdint>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_camera.h"

namespace hd::drivers::testing {

struct MailboxWatch {
  uint64_t shown = 0;
  uint64_t older_than_shown = 0;  ///< frames presented as new that were not newer: must be 0
  int64_t newest_ns = 0;
  void poll(RtpCamera& cam) {
    if (!cam.frames().fetch()) return;
    const int64_t t = cam.frames().latest().host_timestamp_ns;
    if (t <= newest_ns || t > monotonic_now_ns()) ++older_than_shown;
    newest_ns = std::max(newest_ns, t);
    ++shown;
  }
};

}  // namespace hd::drivers::testing
