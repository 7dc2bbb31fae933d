// RtpCameraCounters::snapshot: the atomics read into RtpCameraStats.
#include "drivers/rtp/rtp_camera_stats.h"

namespace hd::drivers {

RtpCameraStats RtpCameraCounters::snapshot(bool srtp) const {
  constexpr auto relaxed = std::memory_order_relaxed;
  RtpCameraStats s;
  s.packets = packets.load(relaxed);
  s.bytes = bytes.load(relaxed);
  s.feedback_targets = feedback_targets.load(relaxed);
  for (std::size_t i = 0; i < s.malformed.size(); ++i) {
    s.malformed[i] = malformed[i].load(relaxed);
    s.malformed_total += s.malformed[i];
  }
  s.accepted = accepted.load(relaxed);
  s.sequence_resyncs = sequence_resyncs.load(relaxed);
  s.frames_published = frames_published.load(relaxed);
  s.wrong_format = wrong_format.load(relaxed);
  s.key_frames = key_frames.load(std::memory_order_acquire);
  s.last_key_frame_capture_ns = last_key_frame_capture_ns.load(relaxed);
  s.stamped_frames = stamped.load(relaxed);
  s.unstamped_frames = unstamped.load(relaxed);
  s.capture_after_arrival = capture_after_arrival.load(relaxed);
  s.not_newer = not_newer.load(relaxed);
  s.access_units_retimed = access_units_retimed.load(relaxed);
  for (std::size_t i = 0; i < s.stamp_errors.size(); ++i)
    s.stamp_errors[i] = stamp_errors[i].load(relaxed);
  if (srtp) {
    s.srtp_decrypted = decrypted.load(relaxed);
    s.srtp_rejected = s.accepted > s.srtp_decrypted ? s.accepted - s.srtp_decrypted : 0;
  }
  s.last_camera_index = last_camera_index.load(relaxed);
  s.last_calibration_revision = last_calibration_revision.load(relaxed);
  s.sender_reports = sender_reports.load(relaxed);
  s.jitter_too_late = jitter_too_late.load(relaxed);
  s.jitter_over_latency = jitter_over_latency.load(relaxed);
  s.packets_depayloaded = packets_depayloaded.load(relaxed);
  s.frames_decoded = frames_decoded.load(relaxed);
  s.frames_converted = frames_converted.load(relaxed);
  s.frames_arrived = frames_arrived.load(relaxed);
  s.jitter_lost = jitter_lost.load(relaxed);
  s.frames_without_verdict = frames_without_verdict.load(relaxed);
  s.fec_recovered = fec_recovered.load(relaxed);
  s.fec_packets = fec_packets.load(relaxed);
  s.access_units = access_units.load(relaxed);
  s.frames_damaged = frames_damaged.load(relaxed);
  s.refresh_frames = refresh_frames.load(relaxed);
  s.heals_by_refresh = s.refresh_frames > 0;
  return s;
}

}  // namespace hd::drivers
