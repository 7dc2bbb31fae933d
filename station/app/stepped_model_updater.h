#pragma once
// The station's model updater driven by the scene's clock for `hybrid-station score`.

#include <cmath>
#include <cstdint>

#include "render/loop/stepped_clock.h"
#include "station/app/station_parts.h"

namespace hd::station {

/// The model updater on the scene's clock: frames taken every refresh period (on its grid from
/// the first frame, missed slots skipped as its thread does), published the model's delay later.
class SteppedModelUpdater {
 public:
  explicit SteppedModelUpdater(StationParts& p) : p_(p) {
    if (!p.updater) return;
    period_ns_ = std::llround(p.updater->config().refresh_period_s * 1e9);
    delay_ns_ = std::llround(p.updater->config().delay_s * 1e9);
  }
  void advance_to(int64_t now_ns) {
    if (!p_.updater) return;
    auto& clock = static_cast<render::SteppedLoopClock&>(*p_.updater_clock);
    if (!pending_ && (next_ns_ == 0 || now_ns >= next_ns_)) {
      if (next_ns_ == 0) next_ns_ = now_ns;
      clock.set_ns(now_ns);
      pending_ = p_.updater->take_update();
      finish_ns_ = now_ns + delay_ns_;
      while (next_ns_ <= now_ns) next_ns_ += period_ns_;
    }
    if (pending_ && now_ns >= finish_ns_) {
      clock.set_ns(now_ns);
      p_.updater->finish_update();
      pending_ = false;
    }
  }

 private:
  StationParts& p_;
  int64_t period_ns_ = 0, delay_ns_ = 0;
  int64_t next_ns_ = 0, finish_ns_ = 0;
  bool pending_ = false;
};

}  // namespace hd::station
