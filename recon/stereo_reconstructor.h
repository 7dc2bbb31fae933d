#pragma once
// The stereo reconstruction of one camera pair: a pair of frames with their capture times in, the
// pair's depth mesh in workspace coordinates and what it cost out. Runs off the render thread (the
// model updater calls it at the model's rate; hybrid-recon calls it once).

#include <cstdint>
#include <string>
#include <string_view>

#include "recon/depth_mesh.h"
#include "recon/disparity_filter.h"
#include "recon/disparity_matcher.h"
#include "recon/rectification.h"
#include "recon/row_error.h"
#include "recon/stereo_image.h"
#include "recon/stereo_rig.h"

namespace hd::recon {

struct ReconstructionConfig {
  MatcherConfig matcher;
  FilterConfig filter;
  DepthMeshConfig mesh;
  double rectify_alpha = 0.0;  ///< cv::stereoRectify's alpha (0: no black border)
  /// A pair whose capture times differ by more than this is refused: a moving object would be
  /// at two places. 10 ms: an arm moving at 0.3 m/s moves 3 mm.
  int64_t max_pair_skew_ns = 10'000'000;
  bool measure_row_error = true;

  void check() const;  ///< throws std::invalid_argument naming the field
};

enum class PairStatus {
  kOk,
  kMissingFrame,      ///< one image (or both) absent or of the wrong type
  kSizeMismatch,      ///< an image not of its camera's calibrated size
  kUnsynchronised,    ///< capture times further apart than max_pair_skew_ns
  kNotNewer,          ///< not newer than the last pair reconstructed: old data is not new
  kNoValidDisparity,  ///< nothing matched (no texture, nothing in range, cameras see apart)
};
std::string_view to_string(PairStatus s);

struct ReconstructionStats {
  int64_t capture_ns = 0;  ///< the older of the two capture times: what the mesh shows is that old
  int64_t pair_skew_ns = 0;
  double prepare_ms = 0.0;  ///< colour conversion and rectification of both images
  double match_ms = 0.0;
  double filter_ms = 0.0;
  double mesh_ms = 0.0;
  double row_error_ms = 0.0;
  double total_ms = 0.0;
  double density = 0.0;  ///< known disparities / rectified pixels
  FilterCounts filter;
  RowError row_error;
  std::size_t vertices = 0, triangles = 0;
};

struct Reconstruction {
  PairStatus status = PairStatus::kOk;
  std::string message;  ///< why a pair was refused (names the camera), "" when ok
  DepthMesh mesh;       ///< workspace coordinates; empty unless ok
  ReconstructionStats stats;
  cv::Mat disparity;       ///< filtered, rectified left pixels, CV_32F, NaN = unknown
  cv::Mat left_rectified;  ///< BGR, for reports
};

class StereoReconstructor {
 public:
  /// Rectifies the rig and checks that the cameras share a view within the depths the disparity
  /// range covers. Throws RigError (message names the camera / reason) or std::invalid_argument
  /// (a config field).
  StereoReconstructor(const StereoRig& rig, const ReconstructionConfig& config);

  const Rectification& rectification() const { return rect_; }
  const ReconstructionConfig& config() const { return config_; }
  /// Depths [near, far] (metres, rectified axis) the disparity range can measure.
  double nearest_m() const { return rect_.depth_m(config_.matcher.max_disparity_px()); }
  double farthest_m() const { return rect_.depth_m(config_.matcher.min_disparity_px); }
  double overlap() const { return overlap_; }

  /// Reconstructs one pair into `out` (its buffers reused). A pair refused before matching
  /// (missing, wrongly sized, unsynchronised, not newer) leaves the status and message and an
  /// empty mesh and does not count as the newest pair; a pair matched without a valid disparity
  /// (kNoValidDisparity) does count: it was measured, and showed nothing.
  void reconstruct(const StereoImage& left, const StereoImage& right, Reconstruction& out);

 private:
  ReconstructionConfig config_;
  Rectification rect_;
  DisparityMatcher matcher_;
  double overlap_ = 0.0;
  bool have_last_ = false;
  int64_t last_capture_ns_ = 0;
  cv::Mat left_bgr_, right_bgr_, right_rect_, left_grey_, right_grey_;
  FilterScratch scratch_;
};

}  // namespace hd::recon
