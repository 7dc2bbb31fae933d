// RtpCamera's counters: stats() (its own, the pipeline's, the calibrations', the clock's) and,
// as a CameraLink, them with the RTCP feedback in the station's terms (link_report()).
#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_camera.h"

namespace hd::drivers {

LinkReport RtpCamera::link_report() const {
  const RtpCameraStats st = stats();
  const Feedback fb = feedback();
  LinkReport r;
  r.security =
      config_.srtp_key ? "SRTP AES-128-GCM (key file " + config_.srtp_key->file + ")" : "none";
  r.packets = st.packets;
  r.bytes = st.bytes;
  r.malformed = st.malformed_total;
  r.srtp_rejected = st.srtp_rejected;
  r.frames_stamped = st.stamped_frames;
  r.frames_unstamped = st.unstamped_frames;
  r.not_newer = st.not_newer;
  r.bus_errors = st.bus_errors;
  r.pli_sent = fb.pli_sent;
  r.nack_sent = fb.nack_sent;
  r.rtx_received = fb.rtx_received;
  r.view_feedback_sent = fb.view_feedback_sent;
  r.calibration_errors = st.calibration_errors_total;
  r.last_error = st.last_error;
  r.clock_mapping = to_string(st.clock.kind);
  r.clock_offset_ns = st.clock.offset_ns;
  r.clock_uncertainty_ns = st.clock.uncertainty_ns;
  r.clock_round_trip_ns = st.clock.round_trip_ns;
  r.clock_samples = st.clock.samples;
  r.sender_reports = st.sender_reports;
  r.capture_after_arrival = st.capture_after_arrival;
  return r;
}

ClockMapping RtpCamera::clock_mapping() const {
  return stamper_.clock_mapping(monotonic_now_ns());
}

uint64_t RtpCamera::dropped_frames() const {
  return counters_.wrong_format.load(std::memory_order_relaxed);
}

RtpCameraStats RtpCamera::stats() const {
  RtpCameraStats s = counters_.snapshot(config_.srtp_key.has_value());
  s.bus_errors = pipeline_.errors();
  s.restarts = pipeline_.restarts();
  s.last_error = pipeline_.last_error();
  const RtpCalibrationCache::Counts c = calibrations_.counts();
  s.calibration_errors = c.refused;
  s.calibration_errors_total = c.refused_total;
  s.calibrations_received = c.received;
  s.frames_with_calibration = c.frames_with_calibration;
  s.calibration_size_mismatch = c.size_mismatch;
  s.calibration = calibrations_.newest();
  s.clock = clock_mapping();
  return s;
}

}  // namespace hd::drivers
