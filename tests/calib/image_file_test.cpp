// calib/image_file against OpenCV's imgcodecs, its peer: every file of the shared sets and images
// of each format and layout written by cv::imwrite must read back as cv::imread(IMREAD_UNCHANGED)
// + the conversion to gray gave them (what hybrid-calib did before it stopped loading imgcodecs).
#include <gtest/gtest.h>

#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "calib/image_file.h"
#include "calib/image_set.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

cv::Mat peer_gray(const fs::path& f) {
  return to_gray(cv::imread(f.string(), cv::IMREAD_UNCHANGED));
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(ImageFile, SharedPhotoSetsReadAsImgcodecsReadsThem) {
  int files = 0;
  for (const char* set : {"opencv-left", "webcam-7x7"})  // gray and colour JPEGs
    for (const auto& e : fs::directory_iterator(data_dir(set))) {
      if (!is_image_file_name(e.path())) continue;
      const cv::Mat ours = read_gray_image(e.path());
      EXPECT_TRUE(same(ours, peer_gray(e.path()))) << e.path();
      ++files;
    }
  EXPECT_GE(files, 46);  // 26 + 20
}

TEST(ImageFile, EveryFormatAndLayoutReadsAsImgcodecsReadsIt) {
  ScratchDir dir;
  cv::Mat bgr(37, 53, CV_8UC3), bgra(37, 53, CV_8UC4), gray(37, 53, CV_8UC1);
  cv::randu(bgr, 0, 256);
  cv::randu(bgra, 0, 256);
  cv::randu(gray, 0, 256);
  struct Case {
    std::string name;
    const cv::Mat* image;
  };
  const std::vector<Case> cases = {{"g.png", &gray}, {"c.png", &bgr},  {"a.png", &bgra},
                                   {"g.bmp", &gray}, {"c.bmp", &bgr},  {"g.pgm", &gray},
                                   {"c.ppm", &bgr},  {"g.tif", &gray}, {"c.tiff", &bgr},
                                   {"a.tif", &bgra}, {"g.jpg", &gray}, {"c.JPEG", &bgr}};
  for (const auto& c : cases) {
    const fs::path f = dir.path() / c.name;
    ASSERT_TRUE(cv::imwrite(f.string(), *c.image)) << f;
    const cv::Mat ours = read_gray_image(f);
    EXPECT_EQ(ours.type(), CV_8UC1) << f;
    EXPECT_TRUE(same(ours, peer_gray(f))) << f;
  }
}

TEST(ImageFile, SixteenBitAndBrokenFilesAreRefusedNamingTheFile) {
  ScratchDir dir;
  cv::Mat deep(20, 30, CV_16UC1, cv::Scalar(1000));
  for (const char* name : {"deep.png", "deep.tif"}) {
    const fs::path f = dir.path() / name;
    ASSERT_TRUE(cv::imwrite(f.string(), deep));
    try {
      read_gray_image(f);
      ADD_FAILURE() << f << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(f.string() + ": not an 8-bit image"), std::string::npos)
          << e.what();
    }
  }
  for (const char* name : {"broken.jpg", "broken.png", "broken.bmp", "broken.tif", "x.gif"}) {
    const fs::path f = dir.path() / name;
    std::ofstream(f) << "this is not an image";
    EXPECT_THROW(read_gray_image(f), InputError) << f;
  }
  EXPECT_THROW(read_gray_image(dir.path() / "missing.png"), InputError);
}

TEST(ImageFile, PngBytesDecodeToTheImage) {
  cv::Mat bgr(41, 29, CV_8UC3), bgra(41, 29, CV_8UC4), gray(41, 29, CV_8UC1);
  cv::randu(bgr, 0, 256);
  cv::randu(bgra, 0, 256);
  cv::randu(gray, 0, 256);
  for (const cv::Mat* m : {&gray, &bgr, &bgra}) {
    const std::string png = encode_png(*m);
    const cv::Mat back =
        cv::imdecode(std::vector<uchar>(png.begin(), png.end()), cv::IMREAD_UNCHANGED);
    EXPECT_TRUE(same(back, *m)) << m->channels() << " channels";
  }
  // A view into a larger image (not continuous) encodes as that view.
  const cv::Mat part = bgr(cv::Rect(3, 4, 10, 12));
  const std::string png = encode_png(part);
  EXPECT_TRUE(
      same(cv::imdecode(std::vector<uchar>(png.begin(), png.end()), cv::IMREAD_UNCHANGED), part));
  EXPECT_THROW(encode_png(cv::Mat(4, 4, CV_16UC1)), std::runtime_error);
}

}  // namespace
}  // namespace hd::calib::test
