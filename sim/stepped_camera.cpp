#include "sim/stepped_camera.h"

#include <algorithm>

namespace hd::sim {
namespace {

drivers::Frame prototype(const SceneCamera& c) {
  drivers::Frame f;
  f.allocate_rgba(c.p_c.width, c.p_c.height);
  return f;
}

}  // namespace

SteppedCamera::SteppedCamera(Simulation& sim, std::size_t index, int64_t epoch_ns)
    : sim_(sim),
      index_(index),
      epoch_ns_(epoch_ns),
      id_("sim:" + sim.scene().cameras.at(index).name),
      format_{sim.scene().cameras[index].p_c.width, sim.scene().cameras[index].p_c.height,
              drivers::PixelFormat::kRgba8, sim.scene().cameras[index].rate_hz},
      mailbox_(prototype(sim.scene().cameras[index])) {}

drivers::FormatNegotiation SteppedCamera::negotiate(const drivers::CameraFormatRequest& wanted) {
  drivers::FormatNegotiation n{format_, "", "", ""};
  if (wanted.width_px > 0 && wanted.height_px > 0 &&
      (wanted.width_px != format_.width_px || wanted.height_px != format_.height_px))
    n.limits = "only its scene size " + drivers::size_text(format_.width_px, format_.height_px);
  return n;
}

drivers::SourceState SteppedCamera::state() const {
  return running_ ? drivers::SourceState::kStreaming : drivers::SourceState::kClosed;
}

bool SteppedCamera::advance_to(int64_t now_ns) {
  if (!running_) return false;
  bool have = false;
  uint64_t newest = 0;
  for (;;) {
    const SimFrameTiming t = sim_.frame_timing(index_, next_sequence_);
    const int64_t due =
        std::max(epoch_ns_ + t.exposure_offset_ns + t.delivery_delay_ns, last_delivery_ns_);
    if (due > now_ns) break;
    last_delivery_ns_ = due;  // a drop holds the device's thread up to its slot too
    if (t.dropped) {
      ++dropped_;
    } else {
      newest = next_sequence_;
      have = true;
    }
    ++next_sequence_;
  }
  if (!have) return false;
  drivers::Frame& f = mailbox_.write_slot();
  sim_.render_frame(index_, newest, f);
  f.host_timestamp_ns += epoch_ns_;
  f.device_timestamp_ns += epoch_ns_;
  mailbox_.publish();
  ++delivered_;
  return true;
}

}  // namespace hd::sim
