#include "recon/stereo_reconstructor.h"

#include <chrono>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace hd::recon {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void to_bgr(const StereoImage& in, cv::Mat& out) {
  switch (in.order) {
    case ChannelOrder::kBgr:
      out = in.pixels;
      return;
    case ChannelOrder::kRgba:
      cv::cvtColor(in.pixels, out, cv::COLOR_RGBA2BGR);
      return;
    case ChannelOrder::kGrey:
      cv::cvtColor(in.pixels, out, cv::COLOR_GRAY2BGR);
      return;
  }
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

}  // namespace

void ReconstructionConfig::check() const {
  matcher.check();
  filter.check();
  mesh.check();
  if (!(rectify_alpha >= 0.0 && rectify_alpha <= 1.0))
    throw std::invalid_argument("rectify_alpha: must be in 0..1");
  if (max_pair_skew_ns < 0) throw std::invalid_argument("max_pair_skew_ns: must be >= 0");
}

std::string_view to_string(PairStatus s) {
  switch (s) {
    case PairStatus::kOk:
      return "ok";
    case PairStatus::kMissingFrame:
      return "missing frame";
    case PairStatus::kSizeMismatch:
      return "size mismatch";
    case PairStatus::kUnsynchronised:
      return "unsynchronised";
    case PairStatus::kNotNewer:
      return "not newer";
    case PairStatus::kNoValidDisparity:
      return "no valid disparity";
  }
  return "?";
}

StereoReconstructor::StereoReconstructor(const StereoRig& rig, const ReconstructionConfig& config)
    : config_((config.check(), config)),
      rect_(rig, config.rectify_alpha),
      matcher_(config.matcher) {
  overlap_ = rect_.overlap_fraction(nearest_m(), farthest_m());
  if (overlap_ <= 0.0)
    throw RigError(
        "the cameras do not see a common part of the workspace at the depths the "
        "disparity range covers (" +
        std::to_string(nearest_m()) + " to " + std::to_string(farthest_m()) +
        " m): the right camera sees none of the left camera's view");
}

void StereoReconstructor::reconstruct(const StereoImage& left, const StereoImage& right,
                                      Reconstruction& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out.mesh.clear();
  out.message.clear();
  out.stats = ReconstructionStats{};
  auto refuse = [&](PairStatus s, std::string msg) {
    out.status = s;
    out.message = std::move(msg);
    out.stats.total_ms = ms_since(t0);
  };
  const std::string lc = left.check(), rc = right.check();
  if (!lc.empty()) return refuse(PairStatus::kMissingFrame, "left camera: " + lc);
  if (!rc.empty()) return refuse(PairStatus::kMissingFrame, "right camera: " + rc);
  const StereoRig& rig = rect_.rig();
  if (left.pixels.cols != rig.left.width || left.pixels.rows != rig.left.height)
    return refuse(PairStatus::kSizeMismatch,
                  "left camera: image is " + size_text(left.pixels.cols, left.pixels.rows) +
                      ", its calibration " + size_text(rig.left.width, rig.left.height));
  if (right.pixels.cols != rig.right.width || right.pixels.rows != rig.right.height)
    return refuse(PairStatus::kSizeMismatch,
                  "right camera: image is " + size_text(right.pixels.cols, right.pixels.rows) +
                      ", its calibration " + size_text(rig.right.width, rig.right.height));
  const int64_t skew = std::llabs(left.capture_ns - right.capture_ns);
  out.stats.pair_skew_ns = skew;
  if (skew > config_.max_pair_skew_ns)
    return refuse(PairStatus::kUnsynchronised,
                  "the frames were captured " + std::to_string(skew / 1000) +
                      " us apart (at most " + std::to_string(config_.max_pair_skew_ns / 1000) +
                      " us)");
  const int64_t capture = std::min(left.capture_ns, right.capture_ns);
  out.stats.capture_ns = capture;
  if (have_last_ && capture <= last_capture_ns_)
    return refuse(PairStatus::kNotNewer, "the pair is not newer than the last one reconstructed");

  to_bgr(left, left_bgr_);
  to_bgr(right, right_bgr_);
  rect_.rectify_left(left_bgr_, out.left_rectified);
  rect_.rectify_right(right_bgr_, right_rect_);
  cv::cvtColor(out.left_rectified, left_grey_, cv::COLOR_BGR2GRAY);
  out.stats.prepare_ms = ms_since(t0);

  auto t = std::chrono::steady_clock::now();
  matcher_.compute(out.left_rectified, right_rect_, out.disparity);
  out.stats.match_ms = ms_since(t);
  t = std::chrono::steady_clock::now();
  cv::cvtColor(right_rect_, right_grey_, cv::COLOR_BGR2GRAY);
  out.stats.filter = filter_disparity(left_grey_, right_grey_, matcher_.config(), config_.filter,
                                      out.disparity, scratch_);
  out.stats.filter_ms = ms_since(t);
  const double pixels = static_cast<double>(out.disparity.total());
  out.stats.density = out.stats.filter.known / pixels;
  have_last_ = true;
  last_capture_ns_ = capture;
  if (out.stats.filter.known == 0)
    return refuse(PairStatus::kNoValidDisparity,
                  "no pixel has a trustworthy disparity (no texture, nothing within " +
                      std::to_string(nearest_m()) + " to " + std::to_string(farthest_m()) +
                      " m, or the cameras see different things)");

  t = std::chrono::steady_clock::now();
  build_depth_mesh(out.disparity, rect_, out.left_rectified, config_.mesh, out.mesh);
  out.stats.mesh_ms = ms_since(t);
  out.stats.vertices = out.mesh.positions_m.size();
  out.stats.triangles = out.mesh.triangles.size();
  if (config_.measure_row_error) {
    t = std::chrono::steady_clock::now();
    out.stats.row_error = measure_row_error(left_grey_, right_grey_, out.disparity);
    out.stats.row_error_ms = ms_since(t);
  }
  out.status = PairStatus::kOk;
  out.stats.total_ms = ms_since(t0);
}

}  // namespace hd::recon
