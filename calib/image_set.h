#pragma once
// The calibration images of one folder, all-or-nothing: one bad file stops the run with its name.

#include <filesystem>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace hd::calib {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct NamedImage {
  std::string name;  ///< file name without folder
  cv::Mat gray;      ///< 8-bit single channel
};

/// Image files whose name matches the shell pattern `name_pattern` (fnmatch, e.g. "left*") and
/// ending in (.jpg .jpeg .png .bmp .tif .tiff .pgm .ppm, any case) of `dir`, sorted by name.
/// Throws InputError: missing/empty folder, an unreadable image, an image whose size differs
/// from the first one (naming both sizes).
std::vector<NamedImage> load_image_set(const std::filesystem::path& dir,
                                       const std::string& name_pattern = "*");

/// Converts any 8-bit 1/3/4 channel image to gray.
cv::Mat to_gray(const cv::Mat& image);

}  // namespace hd::calib
