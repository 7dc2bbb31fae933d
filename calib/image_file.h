#pragma once
// Reads calibration images and writes the report picture without OpenCV's imgcodecs.
//
// Why not cv::imread: loading libopencv_imgcodecs (and the GDAL, GDCM, HEIF, ... it links)
// costs ~55 ms of CPU at every start of the program, a quarter of what OpenCV's whole
// calibration sample spends on the 13 shared views (bench/calib/calib_cpu_bench). The formats
// are decoded by the libraries imgcodecs itself uses for them: libjpeg-turbo (JPEG, and its
// BMP / PPM / PGM loader), libpng, libtiff.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace hd::calib {

/// File name endings read_gray_image reads (lower case): .jpg .jpeg .png .bmp .tif .tiff .pgm
/// .ppm.
bool is_image_file_name(const std::filesystem::path& file);

/// The 8-bit gray image in `file`: gray files as they are, colour ones (RGB / BGR, alpha
/// ignored) through cv::cvtColor as cv::imread(IMREAD_UNCHANGED) + cvtColor gives them (EXIF
/// orientation is not applied, as IMREAD_UNCHANGED does not). Throws InputError naming the file
/// when it is unreadable, not one of those formats, or not 8 bits per sample.
cv::Mat read_gray_image(const std::filesystem::path& file);

/// PNG bytes of an 8-bit gray, BGR or BGRA image (libpng). Throws std::runtime_error otherwise.
std::string encode_png(const cv::Mat& image);

}  // namespace hd::calib
