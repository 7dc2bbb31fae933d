// RtpCamera as a CameraLink: its receive statistics and RTCP feedback in the station's terms.
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

}  // namespace hd::drivers
