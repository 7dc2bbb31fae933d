#pragma once
// Settings of one camera's outgoing stream at the remote site (hybrid-remote), as data.

#include <cstdint>
#include <optional>
#include <string>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/rtp/srtp_key.h"

namespace hd::remote {

/// One camera → one RTP H.264 stream to the station's `rtp://host:port` (RTCP on port + 1).
struct RtpSendConfig {
  std::string host = "127.0.0.1";
  uint16_t port = 5600;
  int width_px = 0;
  int height_px = 0;
  double rate_hz = 30.0;
  int bitrate_kbps = 4000;
  /// The H.264 encoder element (remote/sender/h264_encoder.h: choose_h264_encoder() picks it).
  std::string encoder = "x264enc";
  /// A key frame (IDR, with SPS/PPS) at least this often: a station that joins late, or after
  /// a link cut, decodes within this time even without asking (x264enc key-int-max).
  double key_interval_s = 0.5;
  /// x264enc intra-refresh: after the first IDR no other comes; instead a column of intra
  /// macroblocks sweeps the picture once every key_interval_s (key-int-max frames), each sweep
  /// starting with a recovery point SEI (and SPS/PPS). A loss then heals within the next whole
  /// sweep, in frames no bigger than the others, where an IDR comes as a burst several times a
  /// P-frame's size. The station detects it (drivers/rtp/h264_heal_watch.h). A PLI (or the view
  /// feedback's forced key frame) gets no IDR either: gstx264enc then calls
  /// x264_encoder_intra_refresh, which starts a sweep after the current one (measured in
  /// tests/remote/remote_intra_refresh_test.cpp), so the station sends none. x264enc only: the
  /// hardware encoders' settings differ, so send_pipeline_description refuses others.
  bool intra_refresh = false;
  int payload_type = 96;
  /// RTX (RFC 4588): the last rtx_history_ms of packets are kept (rtprtxsend, rtpbin's aux
  /// sender) and a packet the station NACKs is sent again on its own SSRC with
  /// rtx_payload_type. Off: NACKs are ignored (a plain sender).
  bool retransmission = true;
  int rtx_payload_type = 97;
  int rtx_history_ms = 500;  ///< older packets are past any jitter buffer's deadline
  /// ULP FEC (RFC 5109 as GStreamer's rtpulpfecenc sends it, in the media's SSRC and sequence
  /// numbers, as libwebrtc does): about fec_percentage % more packets, each the XOR of some of
  /// one frame's packets, so the station rebuilds a lost one without a round trip (rtpbin's
  /// request-fec-encoder, ahead of the RTX sender: its repairs keep the sequence numbers the
  /// station asks for). 0: off. Costs the bytes, and the time the jitter buffer waits before it
  /// declares a packet lost (the FEC decoder then tries).
  int fec_percentage = 0;
  int fec_payload_type = 122;
  int rtx_fec_payload_type = 98;  ///< a FEC packet sent again (with retransmission)
  int mtu_bytes = 1200;           ///< below any path's MTU, with room for the header extensions
  /// Bandwidth follows the view (drivers/rtp/view_feedback.h): while the station says it does
  /// not need this camera, only every low_rate_divider-th frame is sent; when it needs it again
  /// the next frame is a key frame. Without a valid message for view_feedback_timeout_s (an old
  /// station, a plain receiver, a station that went away) the camera is sent at full rate.
  bool follow_view = true;  ///< false: every frame whatever the station says (for comparison)
  int low_rate_divider = 6;
  double view_feedback_timeout_s = 2.0;
  uint8_t camera_index = 0;
  uint32_t calibration_revision = 0;
  /// The camera's p_c (core convention, with its distortion) and P_c: with them, the last packet
  /// of every frame carries the calibration element (id 3, drivers/rtp/rtp_calibration.h) with
  /// camera_index and calibration_revision, so the station needs no calibration file. Without,
  /// no element is sent.
  std::optional<core::Pinhole> p_c;
  core::Pose T_world_cam;
  /// RTCP sender reports at least this often (rtpsession rtcp-min-interval; the first comes
  /// after half of it): each one is a sample of the station's clock-offset estimate, and the
  /// first tells the station where its NACK and PLI go; until then a lost packet cannot be
  /// asked for (measured: with 1 s, the first 0.5 s of a 1 % loss link lost two packets for
  /// good, each costing the frames up to the next key frame). RFC 3550 allows 360 / kbit/s
  /// seconds, 90 ms at 4 Mbit/s; 200 ms is ~0.5 KB/s of ~100-byte reports.
  int rtcp_interval_ms = 200;
  /// Tests only: this sender's clock runs this far ahead of the host's CLOCK_REALTIME (its ntp-64
  /// capture times, its RTCP sender reports and the receiver reports' round trip alike), as a
  /// sender at another site would whose clock is off.
  int64_t test_clock_shift_ns = 0;
  /// With a key: SRTP AES-128-GCM (srtpenc) on media and RTCP.
  std::optional<drivers::SrtpKey> srtp_key;

  int key_int_frames() const;  ///< key_interval_s in frames, at least 1
  int vbv_buffer_ms() const;   ///< one frame period, rounded up: VBV of about one frame
};

}  // namespace hd::remote
