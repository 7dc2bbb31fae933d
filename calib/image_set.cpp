#include "calib/image_set.h"

#include <fnmatch.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "calib/image_file.h"

namespace hd::calib {

namespace fs = std::filesystem;

cv::Mat to_gray(const cv::Mat& image) {
  if (image.depth() != CV_8U) return {};
  cv::Mat g;
  switch (image.channels()) {
    case 1:
      g = image;
      break;
    case 3:
      cv::cvtColor(image, g, cv::COLOR_BGR2GRAY);
      break;
    case 4:
      cv::cvtColor(image, g, cv::COLOR_BGRA2GRAY);
      break;
    default:
      break;
  }
  return g;
}

std::vector<NamedImage> load_image_set(const fs::path& dir, const std::string& name_pattern) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string() + ": not a folder");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    if (is_image_file_name(e.path()) &&
        ::fnmatch(name_pattern.c_str(), e.path().filename().c_str(), 0) == 0)
      files.push_back(e.path());
  }
  if (ec) throw InputError(dir.string() + ": cannot list the folder: " + ec.message());
  if (files.empty())
    throw InputError(dir.string() + ": no images (.jpg .png .bmp .tif .pgm .ppm) matching '" +
                     name_pattern + "' in the folder");
  std::sort(files.begin(), files.end());
  std::vector<NamedImage> out;
  for (const auto& f : files) {
    const cv::Mat g = read_gray_image(f);  // throws InputError naming the file
    if (!out.empty() && g.size() != out.front().gray.size())
      throw InputError(
          f.string() + ": image is " + std::to_string(g.cols) + "x" + std::to_string(g.rows) +
          " but " + out.front().name + " is " + std::to_string(out.front().gray.cols) + "x" +
          std::to_string(out.front().gray.rows) + "; one calibration needs one camera mode");
    out.push_back({f.filename().string(), g});
  }
  return out;
}

}  // namespace hd::calib
