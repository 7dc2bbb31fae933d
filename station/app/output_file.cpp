#include "station/app/output_file.h"

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace hd::station {

void write_png_atomically(const cv::Mat& bgr, const std::string& path) {
  // The temp name keeps the .png suffix: imwrite picks the encoder from it.
  const std::string tmp = path + ".tmp.png";
  bool ok = false;
  try {
    ok = cv::imwrite(tmp, bgr);
  } catch (const cv::Exception&) {
    ok = false;
  }
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write PNG");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the temp file into place");
  }
}

void write_text_atomically(const std::string& text, const std::string& path) {
  const std::string tmp = path + ".tmp";
  bool ok = false;
  {
    std::ofstream f(tmp, std::ios::trunc | std::ios::binary);
    ok = static_cast<bool>(f << text) && static_cast<bool>(f.flush());
  }
  std::error_code ec;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the temp file into place");
  }
}

void rgba_to_bgr(const render::ImageRgba8& rgba, cv::Mat& bgr) {
  const cv::Mat view(rgba.height, rgba.width, CV_8UC4, const_cast<uint8_t*>(rgba.data.data()),
                     static_cast<std::size_t>(rgba.stride_bytes));
  cv::cvtColor(view, bgr, cv::COLOR_RGBA2BGR);
}

}  // namespace hd::station
