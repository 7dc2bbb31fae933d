// hybrid-recon: the stereo reconstruction as a what-if tool (DESIGN.md "What we ship").
// A stereo pair and its two calibration files in, the reconstructed surface as a PLY mesh in
// workspace coordinates out; timing and density on stdout. Bad input: exit 2, nothing written.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "calib/atomic_file.h"
#include "calib/calibration_file.h"
#include "recon/ply_writer.h"
#include "recon/stereo_reconstructor.h"

namespace {

constexpr int kExitBadInput = 2;
constexpr int kExitFailed = 1;

const char* const kDescription =
    R"(hybrid-recon: reconstructs the surface a calibrated stereo pair sees (docs/reconstruction.md).

The calibration files are hybrid-calib's (OpenCV FileStorage YAML with camera_matrix,
distortion_coefficients, image_width/height and the workspace pose camera_pose_R/_t).
The left image's pixels index the reconstruction; the right camera must be to its right.
Output: a binary PLY mesh (float x y z in metres, workspace frame; uchar red green blue from the
left image; triangle faces), written whole or not at all. --disparity also writes the filtered
disparity of the rectified left image as a 16-bit PNG (value = disparity * 16, 0 = unknown).
Exit codes: 0 ok, 2 bad input (message names the file), 1 the output could not be written or
the reconstruction failed.)";

struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Camera {
  hd::core::Pinhole pinhole;
  hd::core::Pose pose;
};

Camera read_camera(const std::string& path) {
  hd::calib::CalibrationFile f;
  try {
    f = hd::calib::read_calibration_file(path);
  } catch (const hd::calib::CalibrationFileError& e) {
    throw BadInput(e.what());
  }
  if (!f.camera_pose)
    throw BadInput(path +
                   ": no camera_pose_R / camera_pose_t (place the camera in the workspace "
                   "with `hybrid-calib pose` first)");
  // read_calibration_file already converted the file's OpenCV numbers to core's convention.
  return {f.pinhole, *f.camera_pose};
}

cv::Mat read_image(const std::string& path, const hd::core::Pinhole& cam,
                   const std::string& calib_path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw BadInput(path + ": no such image file");
  const cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) throw BadInput(path + ": cannot read the image (missing or not an image)");
  if (img.cols != cam.width || img.rows != cam.height)
    throw BadInput(path + ": image is " + std::to_string(img.cols) + "x" +
                   std::to_string(img.rows) + " but " + calib_path + " calibrates " +
                   std::to_string(cam.width) + "x" + std::to_string(cam.height));
  return img;
}

std::string png_bytes(const cv::Mat& disparity) {
  cv::Mat d16(disparity.size(), CV_16UC1);
  for (int y = 0; y < disparity.rows; ++y)
    for (int x = 0; x < disparity.cols; ++x) {
      const float d = disparity.at<float>(y, x);
      d16.at<uint16_t>(y, x) =
          d == d ? static_cast<uint16_t>(std::min(65535.0f, std::round(d * 16.0f))) : 0;
    }
  std::vector<uchar> buf;
  cv::imencode(".png", d16, buf);
  return std::string(buf.begin(), buf.end());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription, "hybrid-recon"};
  std::string left_path, right_path, calib_left, calib_right, out_path, disparity_path;
  std::string matcher = "sgbm-scaled";
  hd::recon::ReconstructionConfig cfg;
  bool force = false;
  app.add_option("--left", left_path, "left image (PNG, JPEG...)")->required();
  app.add_option("--right", right_path, "right image")->required();
  app.add_option("--calib-left", calib_left, "left camera's calibration file")->required();
  app.add_option("--calib-right", calib_right, "right camera's calibration file")->required();
  app.add_option("--out", out_path, "PLY mesh to write")->required();
  app.add_option("--disparity", disparity_path, "also write the disparity as a 16-bit PNG");
  app.add_option("--matcher", matcher, "sgbm-scaled (default), sgbm or bm");
  app.add_option("--min-disparity", cfg.matcher.min_disparity_px,
                 "smallest disparity searched, px (>= 1; sets the farthest depth)")
      ->capture_default_str();
  app.add_option("--num-disparities", cfg.matcher.num_disparities_px,
                 "how many disparities are searched (sets the nearest depth)")
      ->capture_default_str();
  app.add_option("--scale", cfg.matcher.scale, "sgbm-scaled: image scale of the matching pass")
      ->capture_default_str();
  app.add_option("--min-texture", cfg.filter.min_texture_dn,
                 "grey-level standard deviation below which a pixel is unknown (0 = off)")
      ->capture_default_str();
  app.add_option("--stride", cfg.mesh.stride_px, "mesh grid spacing, px")->capture_default_str();
  app.add_flag("--force", force, "overwrite existing output files (the old one is kept as .bak)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  try {
    cfg.matcher.kind = hd::recon::matcher_kind_from_string(matcher);
    cfg.check();
    hd::calib::check_output_free(out_path, force);
    if (!disparity_path.empty()) hd::calib::check_output_free(disparity_path, force);
    const Camera L = read_camera(calib_left), R = read_camera(calib_right);
    const cv::Mat li = read_image(left_path, L.pinhole, calib_left);
    const cv::Mat ri = read_image(right_path, R.pinhole, calib_right);
    hd::recon::StereoRig rig{L.pinhole, R.pinhole, L.pose, R.pose};
    std::unique_ptr<hd::recon::StereoReconstructor> recon;
    try {
      recon = std::make_unique<hd::recon::StereoReconstructor>(rig, cfg);
    } catch (const hd::recon::RigError& e) {
      throw BadInput(calib_left + " + " + calib_right + ": " + e.what());
    }
    hd::recon::Reconstruction r;
    recon->reconstruct({li, hd::recon::ChannelOrder::kBgr, 0},
                       {ri, hd::recon::ChannelOrder::kBgr, 0}, r);
    if (r.status != hd::recon::PairStatus::kOk)
      throw BadInput(left_path + " + " + right_path + ": " + r.message);
    const auto& rc = recon->rectification();
    const auto& s = r.stats;
    std::printf(
        "rectified %dx%d, f %.1f px, baseline %.4f m, depths %.3f..%.3f m, overlap %.0f %%\n",
        rc.size().width, rc.size().height, rc.focal_px(), rc.baseline_m(), recon->nearest_m(),
        recon->farthest_m(), 100.0 * recon->overlap());
    std::printf("matcher %s, disparities %d..%d px\n", matcher.c_str(),
                cfg.matcher.min_disparity_px, cfg.matcher.max_disparity_px() - 1);
    std::printf(
        "time: prepare %.1f ms, match %.1f ms, filter %.1f ms, mesh %.1f ms, row error "
        "%.1f ms, total %.1f ms\n",
        s.prepare_ms, s.match_ms, s.filter_ms, s.mesh_ms, s.row_error_ms, s.total_ms);
    std::printf(
        "density %.1f %% (known disparities / rectified pixels); unknown: unmatched %d, "
        "out of range %d, textureless %d, uncorrelated %d, speckles %d\n",
        100.0 * s.density, s.filter.unmatched, s.filter.out_of_range, s.filter.textureless,
        s.filter.uncorrelated, s.filter.speckles);
    if (s.row_error.measured())
      std::printf(
          "row error: median %+.3f px, median |dy| %.3f px, p90 |dy| %.3f px over %d "
          "features\n",
          s.row_error.median_px, s.row_error.median_abs_px, s.row_error.p90_abs_px,
          s.row_error.features);
    else
      std::printf("row error: not measured (fewer than %d matched features)\n",
                  hd::recon::RowError::kMinFeatures);
    try {
      hd::calib::write_file_atomically(
          out_path, hd::recon::ply_bytes(r.mesh, "hybrid-recon " + left_path + " " + right_path),
          force);
      if (!disparity_path.empty())
        hd::calib::write_file_atomically(disparity_path, png_bytes(r.disparity), force);
    } catch (const std::exception& e) {
      std::cerr << "hybrid-recon: " << e.what() << "\n";
      return kExitFailed;
    }
    std::printf("mesh: %zu vertices, %zu triangles -> %s\n", s.vertices, s.triangles,
                out_path.c_str());
  } catch (const hd::calib::OutputExists& e) {
    std::cerr << "hybrid-recon: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const BadInput& e) {
    std::cerr << "hybrid-recon: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "hybrid-recon: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {  // OpenCV or the allocator: no crash, a message
    std::cerr << "hybrid-recon: reconstruction failed: " << e.what() << "\n";
    return kExitFailed;
  }
  return 0;
}
