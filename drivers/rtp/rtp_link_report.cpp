// RtpCamera's counters: stats() (its own, the pipeline's, the calibrations', the clock's) and,
// as a CameraLink, them with the RTCP feedback in the station's terms (link_report()).
#include "drivers/clock/monotonic_clock.h"
#include "drivers/gobject_ptr.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

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
  for (std::size_t i = 0; i < st.malformed.size(); ++i)
    if (st.malformed[i] > 0)
      r.malformed_by_reason.emplace_back(to_string(static_cast<RtpPacketError>(i)),
                                         st.malformed[i]);
  r.srtp_rejected = st.srtp_rejected;
  r.frames_stamped = st.stamped_frames;
  r.frames_unstamped = st.unstamped_frames;
  r.not_newer = st.not_newer;
  r.bus_errors = st.bus_errors;
  r.pli_sent = fb.pli_sent;
  r.nack_sent = fb.nack_sent;
  r.rtx_received = fb.rtx_received;
  r.fec_recovered = st.fec_recovered;
  r.lost = st.jitter_lost;
  r.view_feedback_sent = fb.view_feedback_sent;
  r.calibration_errors = st.calibration_errors_total;
  r.last_error = st.last_error;
  r.clock_mapping = to_string(st.clock.kind);
  const int64_t host_offset_ns = realtime_minus_monotonic_ns();
  r.clock_text = describe(st.clock, host_offset_ns);
  r.clock_sites_offset_ns = sites_offset_ns(st.clock, host_offset_ns);
  r.clock_offset_ns = st.clock.offset_ns;
  r.clock_uncertainty_ns = st.clock.uncertainty_ns;
  r.clock_round_trip_ns = st.clock.round_trip_ns;
  r.clock_samples = st.clock.samples;
  r.sender_reports = st.sender_reports;
  r.capture_after_arrival = st.capture_after_arrival;
  r.receive_buffer_asked = st.rtp_buffer.asked_bytes;
  r.receive_buffer_bytes = st.rtp_buffer.got_bytes;
  r.rmem_max_bytes = st.rtp_buffer.rmem_max_bytes;
  r.rtcp_buffer_asked = st.rtcp_buffer.asked_bytes;
  r.rtcp_buffer_bytes = st.rtcp_buffer.got_bytes;
  r.receive_buffer = socket_buffer_text(st.rtp_buffer);
  r.kernel_drops = st.kernel_drops;
  r.jitter_too_late = st.jitter_too_late;
  r.jitter_over_latency = st.jitter_over_latency;
  r.frames_decoded = st.frames_decoded;
  r.frames_converted = st.frames_converted;
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
  measure_sockets();
  const ReceiveSocketWatch::Report sockets = sockets_.report();
  s.rtp_buffer = sockets.rtp;
  s.rtcp_buffer = sockets.rtcp;
  s.kernel_drops = sockets.kernel_drops;
  s.jitter_buffer_latency_ms = latency_ms_.load(std::memory_order_relaxed);
  s.frame_end_requests = frame_end_->requests();
  {
    std::lock_guard lock(budget_mutex_);
    s.transit_spread_ms = double(budget_.spread_ns()) * 1e-6;
    s.repair_spread_ms = double(budget_.repair_spread_ns()) * 1e-6;
    s.repair_round_trip_ms = double(budget_.round_trip_ns()) * 1e-6;
  }
  return s;
}

// udpsrc's sockets as they are now (a closed one, after stop(), keeps its last figures).
void RtpCamera::measure_sockets() const {
  auto socket_of = [this](const char* name) {
    GSocket* socket = nullptr;
    if (const GstElementPtr e = pipeline_.find(name))
      g_object_get(e.get(), "used-socket", &socket, nullptr);
    return GObjectPtr<GSocket>(socket);
  };
  const GObjectPtr<GSocket> rtp = socket_of(rtp_elements::kRtpSource);
  const GObjectPtr<GSocket> rtcp = socket_of(rtp_elements::kRtcpSource);
  sockets_.measure(rtp.get(), rtcp.get());
}

}  // namespace hd::drivers
