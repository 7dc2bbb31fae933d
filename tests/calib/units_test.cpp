// The pieces on their own: board spec, file reader, atomic writes, model comparison, coverage,
// live capture from a CameraSource.
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "calib/atomic_file.h"
#include "calib/calibration_file.h"
#include "calib/coverage.h"
#include "calib/cross_validation.h"
#include "calib/image_set.h"
#include "calib/larger_board_probe.h"
#include "calib/live_capture.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

TEST(Board, ParsesAndLaysOutCorners) {
  const Board b = Board::parse("9x6", 0.025);
  EXPECT_EQ(b.cols, 9);
  EXPECT_EQ(b.rows, 6);
  const auto p = b.object_points();
  ASSERT_EQ(p.size(), 54u);
  EXPECT_FLOAT_EQ(p[1].x, 0.025f);  // row-major: next corner along the first row
  EXPECT_FLOAT_EQ(p[9].y, 0.025f);  // first corner of the second row
  EXPECT_FLOAT_EQ(p[53].x, 0.2f);
  EXPECT_THROW(Board::parse("9x6", 0.0), std::invalid_argument);
  EXPECT_THROW(Board::parse("9*6", 0.1), std::invalid_argument);
}

TEST(CrossValidation, IdenticalModelsAgreeAndAScaleErrorShowsInFull) {
  const cv::Size size(640, 480);
  const cv::Matx33d K(500, 0, 320, 0, 500, 240, 0, 0, 1);
  const cv::Mat D = cv::Mat::zeros(1, 5, CV_64F);
  const auto same = compare_models(K, D, K, D, size);
  EXPECT_LT(same.max_px, 1e-3);
  // fx, fy 1% larger: no rotation can absorb a scale about the principal point, so the
  // disagreement is 1% of each grid point's distance from (cx, cy); the grid (32x24 cell
  // centres) reaches (630, 470): 0.01 * hypot(310, 230).
  const cv::Matx33d K2(505, 0, 320, 0, 505, 240, 0, 0, 1);
  const auto scaled = compare_models(K, D, K2, D, size);
  EXPECT_NEAR(scaled.max_px, 0.01 * std::hypot(310.0, 230.0), 0.05);
  // A 2 px shift of the principal point is mostly a camera pan, which calibration puts into the
  // extrinsics.
  const cv::Matx33d K3(500, 0, 322, 0, 500, 240, 0, 0, 1);
  // The rotation absorbs most of it; what is left is the second-order part near the edges.
  const double shifted = compare_models(K, D, K3, D, size).max_px;
  EXPECT_LT(shifted, 1.0);
  EXPECT_GT(shifted, 0.0);
}

TEST(Coverage, HullAndGridOfAKnownRectangle) {
  // Corners filling the top-left quarter of a 640x480 image exactly.
  std::vector<cv::Point2f> v;
  for (int y = 0; y <= 4; ++y)
    for (int x = 0; x <= 4; ++x) v.emplace_back(x * 80.f, y * 60.f);  // 0..320 x 0..240
  const Coverage c = image_coverage({v}, cv::Size(640, 480));
  EXPECT_NEAR(c.hull_fraction, 0.25, 1e-9);
  EXPECT_NEAR(c.board_size_min, 0.25, 1e-9);
  // Cells are 80x80: x = 0..320 touches columns 0..4, y = 0..240 rows 0..3 -> 5 * 4 = 20 of 48.
  EXPECT_NEAR(c.grid_fraction, 20.0 / 48.0, 1e-12);
  EXPECT_EQ(c.occupancy.at<int>(0, 0), 2);  // (0, 0) and (0, 60): cells are 80 px tall
}

TEST(AtomicFile, KeepsBackupAndLeavesNoTemp) {
  ScratchDir d;
  const auto p = d.path() / "a.yml";
  write_file_atomically(p, "one\n", false);
  EXPECT_THROW(write_file_atomically(p, "two\n", false), OutputExists);
  write_file_atomically(p, "two\n", true);
  EXPECT_EQ(d.listing(), (std::vector<std::string>{"a.yml", "a.yml.bak"}));
  std::ifstream a(p), b(d.path() / "a.yml.bak");
  std::string sa, sb;
  std::getline(a, sa);
  std::getline(b, sb);
  EXPECT_EQ(sa, "two");
  EXPECT_EQ(sb, "one");
  EXPECT_THROW(write_file_atomically(d.path() / "missing_dir" / "x.yml", "x", false),
               std::runtime_error);
}

void write(const fs::path& p, const std::string& s) {
  std::ofstream(p) << s;
}

const char* kGood =
    "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
    "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
    "   data: [ 500., 0., 320., 0., 501., 240., 0., 0., 1. ]\n"
    "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
    "   data: [ -0.1, 0.01, 0., 0., 0. ]\n";

TEST(CalibrationFileReader, ReadsPinholeAndPose) {
  ScratchDir d;
  const auto p = d.path() / "c.yml";
  write(p, std::string(kGood) +
               "camera_pose_R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
               "   data: [ 0., -1., 0., 1., 0., 0., 0., 0., 1. ]\n"
               "camera_pose_t: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n"
               "   data: [ 1., 2., 3. ]\n");
  const auto f = read_calibration_file(p);
  EXPECT_EQ(f.pinhole.fx, 500.0);
  EXPECT_EQ(f.pinhole.fy, 501.0);
  // The file's cy = 240 is OpenCV's (pixel centres at integers); core's is half a pixel on.
  EXPECT_EQ(f.pinhole.cx, 320.5);
  EXPECT_EQ(f.pinhole.cy, 240.5);
  EXPECT_EQ(f.pinhole.distortion_count, 5);
  EXPECT_EQ(f.pinhole.distortion[0], -0.1);
  ASSERT_TRUE(f.camera_pose);
  // Camera x axis (first column of R) is world +y: X_world = R X_cam + t.
  const Eigen::Vector3d w = f.camera_pose->to_world({1, 0, 0});
  EXPECT_NEAR(w.x(), 1.0, 1e-12);
  EXPECT_NEAR(w.y(), 3.0, 1e-12);
}

std::string error_of(const fs::path& p) {
  try {
    read_calibration_file(p);
  } catch (const CalibrationFileError& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationFileReader, NamesFileAndKeyOnBadInput) {
  ScratchDir d;
  const auto p = d.path() / "c.yml";
  EXPECT_NE(error_of(p).find("no such calibration file"), std::string::npos);
  write(p, "not: [yaml");
  EXPECT_NE(error_of(p).find("c.yml"), std::string::npos);
  std::string s = kGood;
  write(p, s.substr(0, s.find("distortion_coefficients")));
  EXPECT_NE(error_of(p).find("c.yml: key 'distortion_coefficients': missing"), std::string::npos)
      << error_of(p);
  std::string bad = kGood;
  bad.replace(bad.find("rows: 5"), 7, "rows: 3");
  bad.replace(bad.find("-0.1, 0.01, 0., 0., 0."), 22, "-0.1, 0.01, 0.");
  write(p, bad);
  EXPECT_NE(error_of(p).find("expected 4, 5 or 8 coefficients, got 3"), std::string::npos)
      << error_of(p);
  write(p, std::string(kGood) +
               "camera_pose_R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
               "   data: [ 2., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
               "camera_pose_t: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n"
               "   data: [ 1., 2., 3. ]\n");
  EXPECT_NE(error_of(p).find("key 'camera_pose_R': not a rotation"), std::string::npos);
  write(p, std::string(kGood) +
               "camera_pose_t: !!opencv-matrix\n   rows: 3\n   cols: 1\n"
               "   dt: d\n   data: [ 1., 2., 3. ]\n");
  EXPECT_NE(error_of(p).find("key 'camera_pose_R': missing while"), std::string::npos);
  std::string neg = kGood;
  neg.replace(neg.find("image_width: 640"), 16, "image_width: -5");
  write(p, neg);
  EXPECT_NE(error_of(p).find("image_width"), std::string::npos);
}

// A CameraSource that plays real photos (and one malformed frame) on its own thread, as a driver
// would: the live loop is tested against the interface, no device needed.
class PhotoCamera : public drivers::CameraSource {
 public:
  explicit PhotoCamera(std::vector<cv::Mat> images) : images_(std::move(images)) {}
  ~PhotoCamera() override { stop(); }
  std::string id() const override { return "photo-camera"; }
  void open() override {}
  void start() override {
    run_ = true;
    thread_ = std::thread([this] {
      for (std::size_t i = 0; run_; ++i) {
        drivers::Frame& f = box_.write_slot();
        const cv::Mat& img = images_[i % images_.size()];
        if (i == 3) {
          f.allocate_rgba(10, 10);
          f.stride_bytes = 2;  // malformed: stride shorter than a row
        } else {
          f.allocate_rgba(img.cols, img.rows);
          cv::Mat rgba(img.rows, img.cols, CV_8UC4, f.data.data());
          cv::cvtColor(img, rgba, cv::COLOR_GRAY2RGBA);
        }
        f.sequence = i;
        box_.publish();
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
      }
    });
  }
  void stop() override {
    run_ = false;
    if (thread_.joinable()) thread_.join();
  }
  drivers::SourceState state() const override { return drivers::SourceState::kStreaming; }
  uint64_t dropped_frames() const override { return 0; }
  drivers::Mailbox<drivers::Frame>& frames() override { return box_; }

 private:
  std::vector<cv::Mat> images_;
  drivers::Mailbox<drivers::Frame> box_;
  std::thread thread_;
  std::atomic<bool> run_{false};
};

TEST(LiveCapture, CollectsDistinctViewsAndSaysWhenEnough) {
  auto set = load_image_set(data_dir("opencv-left"), "left*");
  std::vector<cv::Mat> imgs;
  for (auto& s : set) imgs.push_back(s.gray);
  PhotoCamera cam(imgs);
  cam.open();
  cam.start();
  LiveOptions opt;
  opt.target_views = 8;
  opt.min_grid_fraction = 0.5;
  opt.min_size_ratio = 1.5;
  // The limit bounds a hang only: on a loaded machine collecting the views is slow.
  opt.max_duration = std::chrono::milliseconds(120000);
  opt.detector.check_larger = false;  // the board size is known here; keeps the ASan run short
  std::vector<std::string> lines;
  const auto res =
      collect_live_views(cam, Board::parse("9x6", 0.025), opt, [&](const LiveStatus& st) {
        lines.push_back(st.message);
        return lines.size() < 400;  // bound the test
      });
  cam.stop();
  EXPECT_TRUE(res.enough) << (lines.empty() ? "" : lines.back());
  EXPECT_GE(res.views.size(), 8u);
  EXPECT_EQ(res.image_size, cv::Size(640, 480));
  // The camera repeats the 13 photos, so repeats must be refused as near-duplicates.
  EXPECT_LE(res.views.size(), 13u);
  // The malformed frame (number 4 published) was counted and named, unless the consumer skipped
  // it because a newer frame had already replaced it in the mailbox.
  bool named = false;
  for (const auto& l : lines) named = named || l.find("photo-camera rejected") != std::string::npos;
  EXPECT_EQ(named, res.frames_rejected > 0);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.back().find("enough varied views"), std::string::npos) << lines.back();
}

}  // namespace
}  // namespace hd::calib::test

namespace hd::calib::test {
namespace {

// Issue 13 item 6: a 0.062 px view among views near 0.05 px was called an outlier (relative
// rules alone: the others scatter so little that mean + 3 sigma is ~0.058). The absolute floor
// keeps it, while a mis-detected view (1.2 px) and the README's left02 (1.22 px among ~0.35) stay
// flagged.
TEST(OutlierViews, NeedAnAbsoluteFloorAsWellAsARelativeOne) {
  std::vector<double> tight = {0.050, 0.049, 0.051, 0.050, 0.048, 0.052, 0.050, 0.049, 0.051,
                               0.050, 0.049, 0.051, 0.050, 0.048, 0.052, 0.050, 0.062};
  for (bool o : outlier_views(tight)) EXPECT_FALSE(o);
  tight.back() = 1.2;
  const auto flagged = outlier_views(tight);
  EXPECT_TRUE(flagged.back());
  for (std::size_t i = 0; i + 1 < flagged.size(); ++i) EXPECT_FALSE(flagged[i]) << i;
  // The relative rule alone still decides among ordinary errors: 0.46 px among ~0.3 px is 0.16 px
  // above the median (above the floor) and beyond mean + 3 sigma.
  const std::vector<double> real = {0.30, 0.31, 0.29, 0.30, 0.32, 0.28, 0.30, 0.31, 0.29, 0.75};
  EXPECT_TRUE(outlier_views(real).back());
}

}  // namespace
}  // namespace hd::calib::test

namespace hd::calib::test {
namespace {

// A fronto-parallel board drawn square by square: inner corners cols x rows at (x0 + 30 c,
// y0 + 30 r), one square of white margin, then `surround` grey.
cv::Mat drawn_board(int cols, int rows, uchar surround) {
  cv::Mat g(480, 640, CV_8UC1, cv::Scalar(surround));
  const int s = 30, x0 = 120, y0 = 90;
  cv::rectangle(g, cv::Rect(x0 - 2 * s, y0 - 2 * s, (cols + 3) * s, (rows + 3) * s),
                cv::Scalar(230), cv::FILLED);
  for (int r = -1; r < rows; ++r)
    for (int c = -1; c < cols; ++c)
      if (((r + c) & 1) == 0)
        cv::rectangle(g, cv::Rect(x0 + c * s, y0 + r * s, s, s), cv::Scalar(25), cv::FILLED);
  cv::GaussianBlur(g, g, cv::Size(0, 0), 1.0);
  return g;
}

std::vector<cv::Point2f> drawn_corners(int cols, int rows, int c0 = 0, int r0 = 0) {
  std::vector<cv::Point2f> v;
  for (int r = r0; r < r0 + rows; ++r)
    for (int c = c0; c < c0 + cols; ++c)
      v.emplace_back(120.f + 30.f * static_cast<float>(c) - 0.5f,
                     90.f + 30.f * static_cast<float>(r) - 0.5f);
  return v;
}

// The probe against boards whose extent is known by construction: the whole 10x7 board does not
// continue (margin or plain surround), any 9x6 part of it does, and a pattern it cannot judge
// asks for the expensive check.
TEST(LargerBoardProbe, ContinuesExactlyWhereTheDrawnBoardDoes) {
  const Board whole = Board::parse("10x7", 0.03), part = Board::parse("9x6", 0.03);
  for (const uchar surround : {uchar{128}, uchar{230}, uchar{20}}) {
    const cv::Mat g = drawn_board(10, 7, surround);
    const LargerBoardProbe p = probe_beyond_edges(g, whole, drawn_corners(10, 7));
    EXPECT_FALSE(p.continues) << int(surround);
    EXPECT_EQ(p.sides_sampled, 4);
    for (const auto& [c0, r0] :
         {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}})
      EXPECT_TRUE(probe_beyond_edges(g, part, drawn_corners(9, 6, c0, r0)).continues)
          << int(surround) << " part at " << c0 << "," << r0;
  }
  const cv::Mat g = drawn_board(10, 7, 128);
  EXPECT_TRUE(probe_beyond_edges(g, whole, {}).continues);  // wrong corner count
  const std::vector<cv::Point2f> same(70, cv::Point2f(300, 200));
  EXPECT_TRUE(probe_beyond_edges(g, whole, same).continues);  // degenerate grid
  const cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(100));     // no checker to compare with
  EXPECT_TRUE(probe_beyond_edges(flat, whole, drawn_corners(10, 7)).continues);
}

}  // namespace
}  // namespace hd::calib::test
