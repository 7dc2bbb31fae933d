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
// frame keeps that PTS.

#include <gst/gst.h>

#include <array>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "drivers/frame.h"

namespace hd::bench {

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
  /// Capture → decoded RGBA in ms of the frames that came out since the last call.
  std::vector<double> take_latencies_ms();
  uint64_t frames_out() const;

  const std::string& description() const { return description_; }

 private:
  void on_payloaded(GstBuffer* rtp, uint64_t pushed_pts);
  void on_depayloader_input(GstBuffer* rtp);
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
  Ring<uint64_t, int64_t> capture_by_pts_;  // sender PTS → capture
  Ring<uint32_t, int64_t> capture_by_rtp_;  // RTP time → capture
  Ring<uint64_t, uint32_t> rtp_by_pts_;     // receiver PTS → RTP time
  std::vector<double> latencies_ms_;
  uint64_t out_ = 0;
};

}  // namespace hd::bench
