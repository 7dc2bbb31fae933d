#pragma once
// The timestamps of everything one displayed frame was made from.

#include <cstdint>

namespace hd::render {

/// One displayed frame. All times are CLOCK_MONOTONIC nanoseconds; 0 means "not present" (e.g. no
/// video on screen). Derived latencies (what the station reports):
///   motion-to-photon to swap    = swap_ns - pose_sample_ns
///   motion-to-photon to display = predicted_display_ns - pose_sample_ns
///   video age                   = predicted_display_ns - video_ns (how old the video looks)
///   model age                   = predicted_display_ns - model_capture_ns (how old the synthetic
///                                 model's textures look: the paper's delayed model)
struct LatencyRecord {
  uint64_t frame = 0;
  int64_t pose_sample_ns = 0;      ///< newest head sample the prediction started from
  int64_t video_ns = 0;            ///< exposure of the frame shown (or its arrival, see below)
  bool video_is_exposure = false;  ///< false: video_ns is the host arrival time
  int64_t texture_update_ns = 0;   ///< video/model data handed to the compositor
  /// Capture time of the oldest camera frame the drawn model's textures came from (0: the
  /// a-priori model, or no model updater).
  int64_t model_capture_ns = 0;
  int64_t render_start_ns = 0;
  int64_t render_end_ns = 0;
  int64_t swap_ns = 0;               ///< present() returned
  int64_t predicted_display_ns = 0;  ///< the time the pose was predicted to
  bool missed_deadline = false;
  /// A network camera's video (drivers::Frame::LinkStages; 0 otherwise): capture (video_ns) →
  /// encoded → sent → received → decoded → shown (predicted_display_ns).
  int64_t video_encoded_ns = 0;
  int64_t video_sent_ns = 0;
  int64_t video_received_ns = 0;
  int64_t video_decoded_ns = 0;
  /// The drawn model's stages after its capture (model_capture_ns): its reconstruction ended
  /// (0: none in that update) → it was in the model (published) → shown (predicted_display_ns).
  /// 0: the a-priori model, or no model updater.
  int64_t model_reconstructed_ns = 0;
  int64_t model_published_ns = 0;
};

enum class LatencyMetric : uint8_t {
  kMotionToSwap,
  kMotionToDisplay,
  kVideoAge,
  kRender,
  kModelAge,
  // The network camera's link, stage by stage (records of network video only).
  kLinkEncode,   ///< capture → encoded
  kLinkSend,     ///< encoded → sent
  kLinkNetwork,  ///< sent → received (network, with the clock offset's error)
  kLinkDecode,   ///< received → decoded (jitter buffer, depayload, decode)
  kLinkShow,     ///< decoded → shown (convert, mailbox, render, the display's wait)
  // The model, stage by stage (records of an updated model only).
  kModelReconstruct,  ///< capture → reconstructed (stereo; records whose update reconstructed)
  kModelPublish,      ///< capture → in the model (the snapshot published)
  kModelShow,         ///< in the model → shown
};

/// to - from when both stages are stamped.
inline bool link_stage(int64_t from_ns, int64_t to_ns, int64_t& out_ns) {
  if (from_ns == 0 || to_ns == 0) return false;
  out_ns = to_ns - from_ns;
  return true;
}

/// The metric in nanoseconds; false when the record lacks a stamp it needs.
inline bool latency_of(const LatencyRecord& r, LatencyMetric m, int64_t& out_ns) {
  switch (m) {
    case LatencyMetric::kMotionToSwap:
      if (r.pose_sample_ns == 0 || r.swap_ns == 0) return false;
      out_ns = r.swap_ns - r.pose_sample_ns;
      return true;
    case LatencyMetric::kMotionToDisplay:
      if (r.pose_sample_ns == 0 || r.predicted_display_ns == 0) return false;
      out_ns = r.predicted_display_ns - r.pose_sample_ns;
      return true;
    case LatencyMetric::kVideoAge:
      if (r.video_ns == 0 || r.predicted_display_ns == 0) return false;
      out_ns = r.predicted_display_ns - r.video_ns;
      return true;
    case LatencyMetric::kRender:
      if (r.render_start_ns == 0 || r.render_end_ns == 0) return false;
      out_ns = r.render_end_ns - r.render_start_ns;
      return true;
    case LatencyMetric::kModelAge:
      if (r.model_capture_ns == 0 || r.predicted_display_ns == 0) return false;
      out_ns = r.predicted_display_ns - r.model_capture_ns;
      return true;
    case LatencyMetric::kLinkEncode:
      return link_stage(r.video_ns, r.video_encoded_ns, out_ns);
    case LatencyMetric::kLinkSend:
      return link_stage(r.video_encoded_ns, r.video_sent_ns, out_ns);
    case LatencyMetric::kLinkNetwork:
      return link_stage(r.video_sent_ns, r.video_received_ns, out_ns);
    case LatencyMetric::kLinkDecode:
      return link_stage(r.video_received_ns, r.video_decoded_ns, out_ns);
    case LatencyMetric::kLinkShow:
      return link_stage(r.video_decoded_ns, r.predicted_display_ns, out_ns);
    case LatencyMetric::kModelReconstruct:
      return link_stage(r.model_capture_ns, r.model_reconstructed_ns, out_ns);
    case LatencyMetric::kModelPublish:
      return link_stage(r.model_capture_ns, r.model_published_ns, out_ns);
    case LatencyMetric::kModelShow:
      return link_stage(r.model_published_ns, r.predicted_display_ns, out_ns);
  }
  return false;
}

}  // namespace hd::render
