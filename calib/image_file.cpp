#include "calib/image_file.h"

#include <png.h>
#include <tiffio.h>
#include <turbojpeg.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "calib/image_set.h"

namespace hd::calib {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

[[noreturn]] void fail(const fs::path& file, const std::string& why) {
  throw InputError(file.string() + ": " + why);
}

std::vector<unsigned char> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "unreadable (cannot open the file)");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (in.bad()) fail(file, "unreadable (read error)");
  return bytes;
}

// 1, 3 (BGR) or 4 (BGRA) channels to gray, as before (cv::cvtColor).
cv::Mat gray_of(const cv::Mat& image, bool rgb_order) {
  cv::Mat g;
  switch (image.channels()) {
    case 1:
      return image;
    case 3:
      cv::cvtColor(image, g, rgb_order ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY);
      return g;
    case 4:
      cv::cvtColor(image, g, rgb_order ? cv::COLOR_RGBA2GRAY : cv::COLOR_BGRA2GRAY);
      return g;
    default:
      return {};
  }
}

struct TjDeleter {
  void operator()(void* h) const { tjDestroy(h); }
};
using TjHandle = std::unique_ptr<void, TjDeleter>;

cv::Mat read_jpeg(const fs::path& file) {
  const std::vector<unsigned char> bytes = read_bytes(file);
  TjHandle tj(tjInitDecompress());
  if (!tj) fail(file, "cannot start the JPEG decoder");
  int w = 0, h = 0, subsamp = 0, colorspace = 0;
  if (tjDecompressHeader3(tj.get(), bytes.data(), static_cast<unsigned long>(bytes.size()), &w, &h,
                          &subsamp, &colorspace) != 0)
    fail(file, std::string("unreadable as JPEG (") + tjGetErrorStr2(tj.get()) + ")");
  // Gray files decode to gray; colour ones to BGR first, as imread does, then to gray the same
  // way as every other colour image.
  const bool gray = colorspace == TJCS_GRAY;
  cv::Mat img(h, w, gray ? CV_8UC1 : CV_8UC3);
  if (tjDecompress2(tj.get(), bytes.data(), static_cast<unsigned long>(bytes.size()), img.data, w,
                    static_cast<int>(img.step), h, gray ? TJPF_GRAY : TJPF_BGR, 0) != 0 &&
      tjGetErrorCode(tj.get()) == TJERR_FATAL)
    fail(file, std::string("unreadable as JPEG (") + tjGetErrorStr2(tj.get()) + ")");
  return gray_of(img, false);
}

// BMP, PPM and PGM through libjpeg-turbo's loader, in the file's own pixel format.
cv::Mat read_with_tj_loader(const fs::path& file) {
  TjHandle tj(tjInitCompress());
  if (!tj) fail(file, "cannot start libjpeg-turbo's image loader");
  int w = 0, h = 0, format = TJPF_UNKNOWN;
  unsigned char* data = tjLoadImage(file.c_str(), &w, 1, &h, &format, 0);
  if (!data) fail(file, std::string("unreadable (") + tjGetErrorStr2(nullptr) + ")");
  std::unique_ptr<unsigned char, decltype(&tjFree)> owned(data, &tjFree);
  cv::Mat out;
  switch (format) {
    case TJPF_GRAY:
      out = cv::Mat(h, w, CV_8UC1, data).clone();
      break;
    case TJPF_RGB:
      out = gray_of(cv::Mat(h, w, CV_8UC3, data), true);
      break;
    case TJPF_BGR:
      out = gray_of(cv::Mat(h, w, CV_8UC3, data), false);
      break;
    default:
      fail(file, "unreadable (unsupported pixel layout)");
  }
  return out;
}

cv::Mat read_png(const fs::path& file) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, file.c_str()))
    fail(file, std::string("unreadable as PNG (") + image.message + ")");
  struct Guard {
    png_image* p;
    ~Guard() { png_image_free(p); }
  } guard{&image};
  if (image.format & PNG_FORMAT_FLAG_LINEAR) fail(file, "not an 8-bit image (16 bits per sample)");
  if (image.format & PNG_FORMAT_FLAG_COLORMAP) image.format &= ~PNG_FORMAT_FLAG_COLORMAP;
  // Palette files expand to their colours; gray stays gray; alpha is kept and then ignored by
  // the conversion to gray, as before.
  const bool color = image.format & PNG_FORMAT_FLAG_COLOR;
  const bool alpha = image.format & PNG_FORMAT_FLAG_ALPHA;
  image.format = color ? (alpha ? PNG_FORMAT_BGRA : PNG_FORMAT_BGR)
                       : (alpha ? PNG_FORMAT_GA : PNG_FORMAT_GRAY);
  const int channels = static_cast<int>(PNG_IMAGE_PIXEL_CHANNELS(image.format));
  cv::Mat img(static_cast<int>(image.height), static_cast<int>(image.width), CV_8UC(channels));
  if (!png_image_finish_read(&image, nullptr, img.data, static_cast<png_int_32>(img.step), nullptr))
    fail(file, std::string("unreadable as PNG (") + image.message + ")");
  if (channels == 2) {  // gray + alpha: the gray plane
    cv::Mat g;
    cv::extractChannel(img, g, 0);
    return g;
  }
  return gray_of(img, false);
}

cv::Mat read_tiff(const fs::path& file) {
  TIFFSetWarningHandler(nullptr);
  std::unique_ptr<TIFF, decltype(&TIFFClose)> tif(TIFFOpen(file.c_str(), "r"), &TIFFClose);
  if (!tif) fail(file, "unreadable as TIFF");
  uint32_t w = 0, h = 0;
  uint16_t bits = 8, spp = 1;
  TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &w);
  TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &h);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &spp);
  if (bits != 8) fail(file, "not an 8-bit image (" + std::to_string(bits) + " bits per sample)");
  cv::Mat rgba(static_cast<int>(h), static_cast<int>(w), CV_8UC4);
  if (!TIFFReadRGBAImageOriented(tif.get(), w, h, reinterpret_cast<uint32_t*>(rgba.data),
                                 ORIENTATION_TOPLEFT, 0))
    fail(file, "unreadable as TIFF (decoding failed)");
  // ABGR in memory order R, G, B, A on little-endian machines. A gray file reads back as
  // R = G = B, which converts to exactly that gray.
  return gray_of(rgba, true);
}

}  // namespace

bool is_image_file_name(const fs::path& file) {
  static const char* const exts[] = {".jpg", ".jpeg", ".png", ".bmp",
                                     ".tif", ".tiff", ".pgm", ".ppm"};
  const std::string ext = lower_extension(file);
  return std::find(std::begin(exts), std::end(exts), ext) != std::end(exts);
}

cv::Mat read_gray_image(const fs::path& file) {
  const std::string ext = lower_extension(file);
  cv::Mat g;
  if (ext == ".jpg" || ext == ".jpeg")
    g = read_jpeg(file);
  else if (ext == ".png")
    g = read_png(file);
  else if (ext == ".tif" || ext == ".tiff")
    g = read_tiff(file);
  else if (ext == ".bmp" || ext == ".pgm" || ext == ".ppm")
    g = read_with_tj_loader(file);
  else
    fail(file, "not an image file this tool reads (.jpg .png .bmp .tif .pgm .ppm)");
  if (g.empty() || g.type() != CV_8UC1) fail(file, "unreadable or not an 8-bit image");
  return g;
}

std::string encode_png(const cv::Mat& image) {
  if (image.depth() != CV_8U ||
      (image.channels() != 1 && image.channels() != 3 && image.channels() != 4))
    throw std::runtime_error("encode_png: need an 8-bit gray, BGR or BGRA image");
  const cv::Mat img = image.isContinuous() ? image : image.clone();
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  p.width = static_cast<png_uint_32>(img.cols);
  p.height = static_cast<png_uint_32>(img.rows);
  p.format = img.channels() == 1   ? PNG_FORMAT_GRAY
             : img.channels() == 3 ? PNG_FORMAT_BGR
                                   : PNG_FORMAT_BGRA;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&p, nullptr, &size, 0, img.data, static_cast<png_int_32>(img.step),
                                 nullptr))
    throw std::runtime_error(std::string("PNG encoding failed: ") + p.message);
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&p, out.data(), &size, 0, img.data,
                                 static_cast<png_int_32>(img.step), nullptr))
    throw std::runtime_error(std::string("PNG encoding failed: ") + p.message);
  out.resize(size);
  return out;
}

}  // namespace hd::calib
