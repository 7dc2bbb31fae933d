#include "calib/image_set.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

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
  static const std::vector<std::string> exts = {".jpg", ".jpeg", ".png", ".bmp",
                                                ".tif", ".tiff", ".pgm", ".ppm"};
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (std::find(exts.begin(), exts.end(), ext) != exts.end() &&
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
    cv::Mat img;
    try {
      img = cv::imread(f.string(), cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      img.release();
    }
    cv::Mat g = img.empty() ? cv::Mat() : to_gray(img);
    if (g.empty()) throw InputError(f.string() + ": unreadable or not an 8-bit image");
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
