// Makes the scenes' photographic textures from the Middlebury "Aloe" left view, aloeL.jpg. Not part
// of the build: SOURCE.md (this folder) says how to build and run it, and where the photograph
// comes from.
// Each texture is a pixel rectangle of the photograph, shrunk with cv::INTER_AREA (a box filter:
// no ringing, JPEG blocks averaged away), optionally flipped, written as an 8-bit RGB PNG.

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <string>

namespace {

struct Crop {
  const char* file;
  cv::Rect source;  ///< pixels of aloeL.jpg (1282 x 1110)
  cv::Size size;    ///< the PNG's size
  bool flip_rows;   ///< stored bottom row first
};

// The PNG's aspect ratio is the surface's, so a texel is square on it.
const Crop kCrops[] = {
    // The back wall (2.4 x 1.3 m): the photograph's full width, its top 694 rows (the plant's
    // leaves in front of the patterned cloth).
    {"aloe-wall.png", {0, 0, 1282, 694}, {384, 208}, false},
    // The table top (1.6 x 1.0 m): the cloth above and left of the plant, no leaf in it. A
    // horizontal quad (ypr [0, 90, 0]) puts the texture's first row at its near edge, so the rows
    // are flipped: the cameras, looking across the table, see the cloth as it was photographed.
    {"aloe-cloth-table.png", {0, 0, 544, 340}, {384, 240}, true},
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s ALOEL_JPG OUT_DIR\n", argv[0]);
    return 2;
  }
  const cv::Mat photo = cv::imread(argv[1], cv::IMREAD_COLOR);
  if (photo.cols != 1282 || photo.rows != 1110) {
    std::fprintf(stderr, "%s: not the 1282 x 1110 aloeL.jpg\n", argv[1]);
    return 1;
  }
  for (const Crop& c : kCrops) {
    cv::Mat out;
    cv::resize(photo(c.source), out, c.size, 0, 0, cv::INTER_AREA);
    if (c.flip_rows) cv::flip(out, out, 0);
    const std::string path = std::string(argv[2]) + "/" + c.file;
    if (!cv::imwrite(path, out, {cv::IMWRITE_PNG_COMPRESSION, 9})) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      return 1;
    }
    std::printf("%s: %d x %d from (%d, %d) %d x %d of aloeL.jpg%s\n", path.c_str(), out.cols,
                out.rows, c.source.x, c.source.y, c.source.width, c.source.height,
                c.flip_rows ? ", rows flipped" : "");
  }
  return 0;
}
