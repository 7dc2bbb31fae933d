#pragma once
// The fair link benchmark's peer: one camera's link as a plain GStreamer pipeline in this
// process, with our caps, encoder settings and conversions (RGBA in → videoconvert → the encoder
// input format → x264enc as h264_encoder_description() sets it up for us → rtph264pay → UDP
// loopback → rtpjitterbuffer 20 ms → rtph264depay → avdec_h264 on one thread → videoconvert →
// RGBA → appsink), fed the same pre-rendered frames. Its latency runs from push() (the capture
// stamp) to the appsink's callback (the decoded RGBA frame available to the consumer), the points
// ours is measured at.
//
// The capture time crosses the UDP hop by the RTP time: the payloader's output maps RTP time →
// capture, the depayloader's input maps the jitter buffer's PTS → RTP time, and the decoded
// frame keeps that PTS. The same maps time the peer's stages at ours' points: encoded (the
// payloader's input), received (the frame's last packet off the socket), decoded (the decoder's
// output) and available (the appsink callback).

#include <gst/gst.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "drivers/frame.h"

namespace hd::bench {

/// One frame through the peer, CLOCK_MONOTONIC ns (0: not seen at that point).
struct PeerFrameTiming {
  int64_t capture_ns = 0, encoded_ns = 0, received_ns = 0, decoded_ns = 0, available_ns = 0;
};

struct PeerLinkConfig {
  int width_px = 1280, height_px = 720, rate_hz = 60, bitrate_kbps = 4000;
  uint16_t port = 0;  ///< loopback UDP port its two halves talk through
};

class PeerLink {
 public:
  explicit PeerLink(const PeerLinkConfig& config);  ///< throws std::runtime_error
  ~PeerLink();
  PeerLink(const PeerLink&) = delete;
  PeerLink& operator=(const PeerLink&) = delete;

  /// Hands `frame` (pre-rendered; it must outlive the run: wrapped, not copied) to the link,
  /// captured at capture_ns (CLOCK_MONOTONIC).
  void push(const drivers::Frame& frame, int64_t capture_ns);
  /// The frames that came out (decoded RGBA available) since the last call.
  std::vector<PeerFrameTiming> take_timings();
  uint64_t frames_out() const;

  const std::string& description() const { return description_; }

 private:
  void on_encoded(uint64_t pushed_pts);
  void on_payloaded(GstBuffer* rtp, uint64_t pushed_pts);
  void on_received(GstBuffer* rtp);
  void on_depayloader_input(GstBuffer* rtp);
  void on_decoded(GstBuffer* frame);
  void on_sample(GstElement* sink);

  // Small rings: a frame crosses the link within a few frame periods.
  template <typename K, typename V>
  struct Ring {
    std::array<std::pair<K, V>, 256> slots{};
    std::size_t next = 0;
    void put(K k, V v) {
      slots[next] = {k, v};
      next = (next + 1) % slots.size();
    }
    void set(K k, V v) {  // the newest value for k (a frame's packets share one RTP time)
      for (auto& [key, value] : slots)
        if (key == k) return void(value = v);
      put(k, v);
    }
    bool get(K k, V& v) const {
      for (const auto& [key, value] : slots)
        if (key == k) return (v = value, true);
      return false;
    }
  };

  std::string description_;
  GstElement* pipeline_ = nullptr;
  GstElement* source_ = nullptr;
  uint64_t period_ns_ = 0, pushed_ = 0;
  mutable std::mutex mutex_;
  Ring<uint64_t, int64_t> capture_by_pts_;         // sender PTS → capture
  Ring<uint64_t, int64_t> encoded_by_pts_;         // sender PTS → encoded
  Ring<uint32_t, PeerFrameTiming> timing_by_rtp_;  // RTP time → capture, encoded, received
  Ring<uint64_t, uint32_t> rtp_by_pts_;            // receiver PTS → RTP time
  Ring<uint32_t, int64_t> decoded_by_rtp_;         // RTP time → decoded
  std::vector<PeerFrameTiming> timings_;
  uint64_t out_ = 0;
};

}  // namespace hd::bench
