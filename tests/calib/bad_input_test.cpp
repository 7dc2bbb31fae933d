// Bad input through the CLI: a clear message naming the file, a non-zero exit, no file left.
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "test_support.h"

namespace hd::calib::test {
namespace {

// Three real views copied into a scratch folder, which each test then spoils in one way.
void copy_views(const fs::path& to, int n = 3) {
  const auto src = data_dir("opencv-left");
  for (int i = 1; i <= n; ++i) {
    const std::string name = "left0" + std::to_string(i) + ".jpg";
    fs::copy_file(src / name, to / name);
  }
}

std::string intrinsics(const fs::path& images, const fs::path& out,
                       const std::string& board = "9x6") {
  return "intrinsics --images " + q(images) + " --board " + board + " --square 0.025 --out " +
         q(out);
}

TEST(BadInput, EmptyFolder) {
  ScratchDir in, out;
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(in.path().string() + ": no images"), std::string::npos) << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, NoBoardInAnyImage) {
  ScratchDir in, out;
  cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  cv::Mat noise(480, 640, CV_8UC1);
  cv::randu(noise, 0, 255);
  cv::imwrite((in.path() / "blank.png").string(), blank);
  cv::imwrite((in.path() / "noise.png").string(), noise);
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("blank.png: no board"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no 9x6 board found in any of the 2 images"), std::string::npos)
      << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, WrongBoardSize) {
  ScratchDir in, out;
  copy_views(in.path());
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml", "8x6"));
  EXPECT_NE(r.exit_code, 0) << r.output;
  // The classic detector finds 8x6 patches of the 9x6 board in some views; the tool must see the
  // larger board around them instead of calibrating on patches.
  EXPECT_NE(r.output.find("part of a larger chessboard"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--board must give ALL inner corners"), std::string::npos) << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, MalformedBoardOption) {
  ScratchDir in, out;
  copy_views(in.path());
  for (const std::string b : {"9", "9x", "x6", "9x6x", "1x6", "-9x6", "9y6"}) {
    const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml", b));
    EXPECT_EQ(r.exit_code, 2) << b << ": " << r.output;
    EXPECT_NE(r.output.find("--board"), std::string::npos) << r.output;
  }
  const auto r = run_cli("intrinsics --images " + q(in.path()) + " --board 9x6 --square -1 --out " +
                         q(out.path() / "c.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--square"), std::string::npos) << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, UnreadableImage) {
  ScratchDir in, out;
  copy_views(in.path());
  std::ofstream(in.path() / "left04.jpg") << "this is not a JPEG";
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("left04.jpg: unreadable"), std::string::npos) << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, TruncatedImage) {
  ScratchDir in, out;
  copy_views(in.path());
  // Half a real JPEG: libjpeg decodes what is there, so the file is read; it must not crash.
  const auto src = data_dir("opencv-left") / "left05.jpg";
  std::ifstream f(src, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), {});
  std::ofstream(in.path() / "left05.jpg", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml"));
  EXPECT_GE(r.exit_code, 0) << r.output;  // not killed by a signal
  EXPECT_NE(r.output.find("left05.jpg"), std::string::npos) << r.output;
}

TEST(BadInput, MismatchedImageSizes) {
  ScratchDir in, out;
  copy_views(in.path());
  cv::Mat small = cv::imread((in.path() / "left03.jpg").string());
  cv::resize(small, small, cv::Size(320, 240));
  cv::imwrite((in.path() / "left03.jpg").string(), small);
  const auto r = run_cli(intrinsics(in.path(), out.path() / "c.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("left03.jpg: image is 320x240 but left01.jpg is 640x480"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(out.listing().empty());
}

TEST(BadInput, ExistingOutputNeedsForceAndIsKeptAsBackup) {
  ScratchDir in, out;
  copy_views(in.path(), 6);
  const auto target = out.path() / "c.yml";
  std::ofstream(target) << "precious: 1\n";
  const auto r = run_cli(intrinsics(in.path(), target));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("already exists; pass --force"), std::string::npos) << r.output;
  EXPECT_EQ(out.listing(), std::vector<std::string>{"c.yml"});
  std::ifstream kept(target);
  std::string line;
  std::getline(kept, line);
  EXPECT_EQ(line, "precious: 1");

  const auto forced = run_cli(intrinsics(in.path(), target) + " --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_EQ(out.listing(), (std::vector<std::string>{"c.yml", "c.yml.bak"}));
  std::ifstream bak(out.path() / "c.yml.bak");
  std::getline(bak, line);
  EXPECT_EQ(line, "precious: 1");
}

TEST(BadInput, PoseWithBrokenIntrinsicsFile) {
  ScratchDir out;
  const auto intr = out.path() / "intr.yml";
  std::ofstream(intr) << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n";
  const auto img = data_dir("webcam-7x7") / "perspectiveimg.jpg";
  const auto r = run_cli("pose --intrinsics " + q(intr) + " --image " + q(img) +
                         " --board 7x7 --square 0.0195 --out " + q(out.path() / "p.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("intr.yml: key 'camera_matrix': missing"), std::string::npos) << r.output;
  EXPECT_EQ(out.listing(), std::vector<std::string>{"intr.yml"});
}

TEST(BadInput, HelpShowsAnExample) {
  const auto r = run_cli("intrinsics --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("Example"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--square"), std::string::npos);
}

}  // namespace
}  // namespace hd::calib::test
