#pragma once
// The network camera's counters (RtpCameraStats, what stats() returns) and the atomics its
// threads count them in.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "drivers/rtp/clock_offset_estimator.h"
#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/rtp_packet.h"
#include "drivers/rtp/rtp_receive_socket.h"

namespace hd::drivers {

/// Counters since start(); read from any thread.
struct RtpCameraStats {
  uint64_t packets = 0;  ///< UDP datagrams that reached the RTP port
  uint64_t bytes = 0;    ///< their UDP payload bytes
  /// Times the RTCP feedback destination was set (the first sender's RTCP address, then each
  /// new one).
  uint64_t feedback_targets = 0;
  /// Packets refused by parse_rtp_packet or check_h264_payload (dropped before rtpbin or, with a
  /// key, right after srtpdec), by reason.
  std::array<uint64_t, static_cast<std::size_t>(RtpPacketError::kCount)> malformed{};
  uint64_t malformed_total = 0;
  uint64_t accepted = 0;  ///< passed on to GStreamer: packets = accepted + malformed_total
  /// Times the stream's sequence numbering was taken anew because two consecutive packets
  /// continued a jump (RtpStreamGuard: a sender that renumbered); the jump's first packet is
  /// counted in malformed[kSequenceJump].
  uint64_t sequence_resyncs = 0;
  uint64_t frames_published = 0;
  uint64_t wrong_format = 0;  ///< decoded frames of another size than negotiated (not published)
  uint64_t bus_errors = 0;    ///< GStreamer errors (each restarts the pipeline)
  /// Frames with the sender's capture time (hybrid-remote) / with their arrival time instead.
  uint64_t stamped_frames = 0;
  uint64_t unstamped_frames = 0;
  /// Stamped frames whose mapped capture time lay after their arrival (the two clocks disagree):
  /// stamped with the arrival instead.
  uint64_t capture_after_arrival = 0;
  /// Decoded frames not newer than the last published one (a late or repeated frame): never
  /// published, so old video is never presented as new.
  uint64_t not_newer = 0;
  /// Access units whose jitter-buffer PTS repeated the previous one's, moved 1 us past it so
  /// that each frame keeps its own stages (drivers/rtp/access_unit_pts.h).
  uint64_t access_units_retimed = 0;
  /// Packets with header extensions whose stamp was refused, by reason (StampError).
  std::array<uint64_t, static_cast<std::size_t>(StampError::kCount)> stamp_errors{};
  /// With a key: packets srtpdec authenticated and decrypted / that failed (a wrong key, or a
  /// sender without encryption): never decoded, never shown.
  uint64_t srtp_decrypted = 0;
  uint64_t srtp_rejected = 0;
  /// Calibration elements (id 3) refused, by reason (CalibrationError); the element is ignored.
  std::array<uint64_t, static_cast<std::size_t>(CalibrationError::kCount)> calibration_errors{};
  uint64_t calibration_errors_total = 0;
  uint64_t calibrations_received = 0;    ///< calibration elements accepted
  uint64_t frames_with_calibration = 0;  ///< published frames that carry the stream's calibration
  /// Decoded frames whose size is not their calibration's image size: never published.
  uint64_t calibration_size_mismatch = 0;
  /// The newest accepted calibration (none: the sender sends none, or none arrived yet).
  std::optional<StreamCalibration> calibration;
  int last_camera_index = -1;  ///< from the camera-state element; -1 none seen
  int64_t last_calibration_revision = -1;
  uint64_t restarts = 0;
  /// Decoded key frames (IDR access units out of the depayloader), and the newest one's capture
  /// time (0: none or unstamped).
  uint64_t key_frames = 0;
  int64_t last_key_frame_capture_ns = 0;
  std::string last_error;       ///< the newest bus error's text ("" none)
  ClockMapping clock;           ///< the sender-clock mapping in use now
  uint64_t sender_reports = 0;  ///< RTCP sender reports received (clock samples)
  /// Where the receive path can drop what arrived, before a frame is shown:
  /// - the sockets' kernel buffers as asked and given (rtp_receive_socket.h), and the datagrams
  ///   the kernel dropped on the RTP socket, its buffer full (-1: not measured yet);
  SocketBuffer rtp_buffer, rtcp_buffer;
  int64_t kernel_drops = -1;
  /// - packets rtpbin's jitter buffer dropped (its drop messages): too late (a later packet had
  ///   already left it, or it had been declared lost), and, with drop-on-latency, its oldest
  ///   packet when it held more than its latency (its output thread, which depayloads, decodes
  ///   and converts, fell behind);
  uint64_t jitter_too_late = 0, jitter_over_latency = 0;
  /// - packets out of the jitter buffer into the depayloader; frames out of avdec_h264; frames
  ///   into the appsink callback (decoded - converted: dropped in between;
  ///   the appsink's max-buffers=1 drop=true never drops, as the callback pulls each sample
  ///   before the next can come); then not_newer, wrong_format and calibration_size_mismatch
  ///   are not published.
  uint64_t packets_depayloaded = 0, frames_decoded = 0, frames_converted = 0;
  /// Frames that reached this host: new RTP times among the stream's packets off the socket
  /// (before any fault injection). frames_published / frames_arrived is the share shown.
  uint64_t frames_arrived = 0;
  /// Repair: the jitter buffer's latency now and the budget it follows (jitter_budget.h), ms;
  /// requests for a frame's missing last packet (frame_end_watch.h).
  int jitter_buffer_latency_ms = 0;
  double transit_spread_ms = 0.0;
  double repair_spread_ms = 0.0;
  double repair_round_trip_ms = 0.0;
  uint64_t frame_end_requests = 0;
  /// Packets the jitter buffer gave up on (its GstRTPPacketLost events, do-lost): each one a
  /// frame not shown, and the frames after it until the stream heals (frames_damaged).
  uint64_t jitter_lost = 0;
  /// Of the packets the jitter buffer gave up on, those the FEC decoder rebuilt (not in
  /// jitter_lost): from FEC, or from a copy that came too late for the jitter buffer and that
  /// rtpstorage, ahead of it, kept.
  uint64_t fec_recovered = 0;
  uint64_t fec_packets = 0;  ///< FEC packets taken (the sender's --fec), before fault injection
  /// Access units out of the depayloader (it drops a fragment without its start; what follows a
  /// loss is judged by the camera: frames_damaged).
  uint64_t access_units = 0;
  /// Frames of a damaged stream (drivers/rtp/h264_heal_watch.h: after a loss, until an intact
  /// IDR, or a recovery point's recovery_frame_cnt intact frames later): a part of the picture is
  /// missing or predicted from a missing part. Never published, only counted: access units
  /// dropped before the decoder (a stream that heals only by IDR) and decoded frames not shown
  /// (one that heals by refresh, whose damaged frames the decoder conceals and the sweep needs).
  uint64_t frames_damaged = 0;
  /// Decoded frames that carry no access unit's mark (access_unit_mark.h): not known to be whole,
  /// not shown.
  uint64_t frames_without_verdict = 0;
  /// The stream carries recovery point SEIs outside IDRs (a sender with intra refresh): no key
  /// frame is asked for after a loss (x264enc would answer with another sweep, not an IDR).
  /// refresh_frames: the newest recovery_frame_cnt + 1, the frames a sweep takes.
  bool heals_by_refresh = false;
  int refresh_frames = 0;
};

/// The counts RtpCamera's threads keep (each counter written by one thread, read by any:
/// relaxed atomics, as none orders anything else). What other parts count (the calibration
/// cache, the pipeline's bus, the view feedback, the clock) joins them in RtpCamera::stats().
struct RtpCameraCounters {
  std::atomic<uint64_t> packets{0}, bytes{0}, feedback_targets{0};
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(RtpPacketError::kCount)> malformed{};
  /// Passed on to rtpbin (with a key: to srtpdec; one found malformed after it is taken back).
  std::atomic<uint64_t> accepted{0};
  std::atomic<uint64_t> decrypted{0};  ///< srtpdec let through, and well formed
  std::atomic<uint64_t> sequence_resyncs{0};
  std::atomic<uint64_t> frames_published{0}, wrong_format{0};
  std::atomic<uint64_t> stamped{0}, unstamped{0}, capture_after_arrival{0}, not_newer{0},
      access_units_retimed{0};
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(StampError::kCount)> stamp_errors{};
  std::atomic<uint64_t> key_frames{0};
  std::atomic<int64_t> last_key_frame_capture_ns{0};
  std::atomic<uint64_t> key_frame_requests{0};
  std::atomic<int> last_camera_index{-1};
  std::atomic<int64_t> last_calibration_revision{-1};
  std::atomic<uint64_t> sender_reports{0};
  std::atomic<uint64_t> jitter_too_late{0}, jitter_over_latency{0};
  std::atomic<uint64_t> packets_depayloaded{0}, frames_decoded{0}, frames_converted{0};
  std::atomic<uint64_t> frames_arrived{0}, jitter_lost{0}, access_units{0}, fec_recovered{0};
  std::atomic<uint64_t> frames_damaged{0}, frames_without_verdict{0}, fec_packets{0};
  std::atomic<int> refresh_frames{0};  ///< 0 until a recovery point SEI outside an IDR was seen
  std::atomic<uint64_t> nacks_sent_at_once{0}, plis_sent_at_once{0};

  void count(RtpPacketError e) {
    malformed[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
  }
  void count(StampError e) {
    stamp_errors[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
  }
  /// These counts as RtpCameraStats (the fields they cover). With `srtp`, srtp_decrypted and
  /// srtp_rejected (accepted but not decrypted: packets in srtpdec's hands a moment ago count as
  /// neither, so rejected never grows from them); without, both 0.
  RtpCameraStats snapshot(bool srtp) const;
};

}  // namespace hd::drivers
