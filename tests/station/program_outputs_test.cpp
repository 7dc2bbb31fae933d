// The run's outputs as units: the frame log, the contact sheet's choice of tiles, the trace
// plot's colours and axes, frames.csv's text, and the recorder's video and PNG frames read back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "station/app/contact_sheet.h"
#include "station/app/frame_log.h"
#include "station/app/frame_recorder.h"
#include "station/app/frames_csv.h"
#include "station/app/run_progress.h"
#include "station/app/trace_plot.h"
#include "support/solid_image.h"

namespace hd::station {
namespace {

namespace fs = std::filesystem;
using core::Variant;

fs::path temp_dir() {
  const fs::path d =
      fs::temp_directory_path() / ("station_outputs_test_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

FrameLogRow row(uint64_t frame, double t_s, Variant v, double m, double w) {
  FrameLogRow r;
  r.decision.frame = frame;
  r.decision.variant = v;
  r.decision.m = m;
  r.decision.w_video = w;
  r.decision.camera = std::isfinite(m) ? 0 : -1;
  r.t_s = t_s;
  return r;
}

// A run of 100 frames at 10 Hz: video, hybrid, synthetic, hybrid, video (20 frames each).
Variant phase(uint64_t i) {
  static const Variant phases[] = {Variant::kVideo, Variant::kHybrid, Variant::kSynthetic,
                                   Variant::kHybrid, Variant::kVideo};
  return phases[i / 20];
}
double w_of(Variant v) {
  return v == Variant::kVideo ? 1.0 : v == Variant::kHybrid ? 0.5 : 0.0;
}
double m_of(Variant v) {
  return v == Variant::kVideo ? 10.0 : v == Variant::kHybrid ? 40.0 : 90.0;
}

TEST(FrameLog, KeepsTheFirstCapacityRowsAndCountsTheRest) {
  FrameLog log(3);
  for (uint64_t i = 0; i < 5; ++i) log.add(row(i, 0.1 * i, Variant::kVideo, 1.0, 1.0));
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log.dropped(), 2u);
  EXPECT_EQ(log[2].decision.frame, 2u);
  EXPECT_EQ(log.end() - log.begin(), 3);
}

render::ImageRgba8 solid(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  return testing::solid_image(w, h, r, g, b);
}

TEST(ThumbnailSet, PicksTheFirstFrameOfEveryPhaseAndSpreadsTheRest) {
  ThumbnailSet t(64, 40, 80, 40, 1);
  const render::ImageRgba8 img = solid(80, 40, 10, 20, 30);
  for (uint64_t i = 0; i < 100; ++i) {
    const Variant v = phase(i);
    t.add(img, {i, 0.1 * i, v, m_of(v), w_of(v)});
  }
  // 100 candidates in 64 slots: decimated once, every 2nd frame kept.
  EXPECT_EQ(t.stride(), 2u);
  EXPECT_EQ(t.size(), 50u);
  const std::vector<std::size_t> picks = t.pick(8);
  ASSERT_EQ(picks.size(), 8u);
  std::vector<uint64_t> frames;
  for (std::size_t i : picks) frames.push_back(t.meta(i).frame);
  // Phase starts 0, 20, 40, 60, 80 and the last candidate (98) are all there.
  for (uint64_t f : {0u, 20u, 40u, 60u, 80u, 98u})
    EXPECT_NE(std::find(frames.begin(), frames.end(), f), frames.end()) << f;
  EXPECT_TRUE(std::is_sorted(frames.begin(), frames.end()));
  // The sheet: 8 tiles of 40x20 in rows of 4, each with its label strip.
  const cv::Mat sheet = t.compose(8, 4);
  EXPECT_EQ(sheet.cols, 4 * (40 + 6) + 6);
  EXPECT_EQ(sheet.rows, 2 * (20 + 22 + 6) + 6);
  // The first tile's pixels are the picture's (BGR of RGB 10, 20, 30; INTER_AREA of a flat image).
  const cv::Vec3b p = sheet.at<cv::Vec3b>(6 + 10, 6 + 20);
  EXPECT_EQ(p, cv::Vec3b(30, 20, 10));
  // Its label strip has the video shade.
  const cv::Scalar shade = variant_shade_bgr(Variant::kVideo);
  const cv::Vec3b l = sheet.at<cv::Vec3b>(6 + 20 + 2, 6 + 38);
  EXPECT_EQ(l, cv::Vec3b(static_cast<uint8_t>(shade[0]), static_cast<uint8_t>(shade[1]),
                         static_cast<uint8_t>(shade[2])));
}

TEST(ThumbnailSet, FlickerIsThinnedToTheRoomItHas) {
  ThumbnailSet t(128, 16, 32, 16, 1);
  const render::ImageRgba8 img = solid(32, 16, 0, 0, 0);
  for (uint64_t i = 0; i < 100; ++i) {
    const Variant v = i % 2 ? Variant::kVideo : Variant::kSynthetic;
    t.add(img, {i, 0.01 * i, v, 1.0, w_of(v)});
  }
  EXPECT_EQ(t.pick(12).size(), 12u);
}

TEST(TracePlot, ShadesEachPhaseWithItsVariantAndLabelsTheAxes) {
  FrameLog log(100);
  for (uint64_t i = 0; i < 100; ++i) {
    const Variant v = phase(i);
    log.add(row(i, 0.1 * i, v, m_of(v), w_of(v)));
  }
  core::TransitionParams tp;
  tp.m_t = 40;
  tp.eps = 10;
  const int W = 1200, H = 720;
  const cv::Mat img = draw_trace(log, tp, W, H);
  ASSERT_EQ(img.cols, W);
  ASSERT_EQ(img.rows, H);
  // Plot area: x from 80 to W - 20 over t in [0, 9.9] s; top panel from y = 40, height
  // (H - 40 - 50 - 50) / 2 = 290; m axis 0..max(2 (m_t + eps), 1.15 p95(m)) = 103.5.
  const int plot_w = W - 100, panel_h = 290, top = 40;
  auto x_at = [&](double t) { return 80 + static_cast<int>(std::lround(t / 9.9 * plot_w)); };
  auto shade_at = [&](double t, int y) {
    const cv::Vec3b p = img.at<cv::Vec3b>(y, x_at(t));
    return cv::Scalar(p[0], p[1], p[2]);
  };
  // Near the top of the m panel (above the curve and the band) the background is the variant's.
  const int y_top = top + 10;
  EXPECT_EQ(shade_at(1.0, y_top), variant_shade_bgr(Variant::kVideo));
  EXPECT_EQ(shade_at(3.0, y_top), variant_shade_bgr(Variant::kHybrid));
  EXPECT_EQ(shade_at(5.0, y_top), variant_shade_bgr(Variant::kSynthetic));
  EXPECT_EQ(shade_at(7.0, y_top), variant_shade_bgr(Variant::kHybrid));
  EXPECT_EQ(shade_at(9.0, y_top), variant_shade_bgr(Variant::kVideo));
  // The m curve in the synthetic phase sits at m = 90 on a 0..103.5 axis (black line).
  const double m_hi = 1.15 * 90.0;
  const int y_m = top + panel_h - static_cast<int>(std::lround(90.0 / m_hi * panel_h));
  const cv::Vec3b c = img.at<cv::Vec3b>(y_m, x_at(5.0));
  EXPECT_LT(c[0] + c[1] + c[2], 3 * 80) << "no dark curve at m = 90";
  // The w_video curve (blue) in the bottom panel at w = 0.5 in the hybrid phase.
  const int bottom = top + panel_h + 50;
  const int y_w = bottom + panel_h - static_cast<int>(std::lround(0.5 * panel_h));
  const cv::Vec3b b = img.at<cv::Vec3b>(y_w, x_at(3.0));
  EXPECT_GT(b[0], b[2] + 60) << "no blue curve at w_video = 0.5";
}

TEST(TracePlot, EmptyLogIsRejected) {
  FrameLog log(1);
  EXPECT_THROW(draw_trace(log, {}), std::invalid_argument);
}

TEST(FramesCsv, WritesInfiniteMAsInfAndNamesTheCamera) {
  const fs::path d = temp_dir();
  FrameLog log(2);
  log.add(row(0, 0.0, Variant::kVideo, 12.5, 1.0));
  FrameLogRow r = row(1, 0.011, Variant::kHybrid, INFINITY, 0.9999991);
  r.missed_deadline = true;
  log.add(r);
  write_frames_csv(log, {"left"}, (d / "frames.csv").string());
  std::ifstream f(d / "frames.csv");
  std::string header, a, b;
  std::getline(f, header);
  std::getline(f, a);
  std::getline(f, b);
  EXPECT_EQ(a.substr(0, 36), "0,0.000000,12.5000,1.000000000,0,lef");
  EXPECT_EQ(b.substr(0, 44), "1,0.011000,inf,0.999999100,-1,,hybrid,1,0,0.");
  EXPECT_FALSE(fs::exists(d / "frames.csv.tmp"));
  fs::remove_all(d);
}

TEST(FramesCsv, UnwritableDirectoryIsNamed) {
  FrameLog log(1);
  log.add(row(0, 0.0, Variant::kVideo, 1.0, 1.0));
  try {
    write_frames_csv(log, {}, "/nonexistent-dir/frames.csv");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/frames.csv"), std::string::npos);
  }
}

TEST(FrameRecorder, VideoAndPngFramesReadBackWithTheirContent) {
  const fs::path d = temp_dir();
  ThumbnailSet thumbs(16, 32, 64, 48, 4);
  FrameRecorderOptions o;
  o.video_path = (d / "run.avi").string();
  o.video_fps = 30.0;
  o.png_every = 5;
  o.png_dir = d.string();
  o.thumbnails = &thumbs;
  // 12 frames: fewer than the ring's slots, so none can be dropped whatever the writer's pace.
  constexpr int kFrames = 12;
  {
    FrameRecorder rec(64, 48, o);
    for (int i = 0; i < kFrames; ++i) {
      const auto g = static_cast<uint8_t>(20 * i);
      rec.offer(solid(64, 48, 200, g, 40),
                {static_cast<uint64_t>(i), i / 30.0, Variant::kVideo, 1.0, 1.0});
    }
    const FrameRecorderStats s = rec.finish();
    EXPECT_EQ(s.video_frames, static_cast<uint64_t>(kFrames));
    EXPECT_EQ(s.dropped, 0u);
    EXPECT_EQ(s.png_frames, 3u);  // frames 0, 5, 10
    EXPECT_EQ(s.thumbnails, 3u);  // frames 0, 4, 8
    EXPECT_TRUE(s.error.empty()) << s.error;
  }
  EXPECT_FALSE(fs::exists(d / "run.avi.tmp.avi"));
  cv::VideoCapture cap((d / "run.avi").string());
  ASSERT_TRUE(cap.isOpened());
  int n = 0;
  cv::Mat f;
  while (cap.read(f)) {
    ASSERT_EQ(f.size(), cv::Size(64, 48));
    // MJPG is lossy: each frame's green level is its index * 20 within JPEG error.
    const cv::Scalar mean = cv::mean(f);
    EXPECT_NEAR(mean[1], 20.0 * n, 6.0) << "frame " << n;
    EXPECT_NEAR(mean[2], 200.0, 6.0);
    ++n;
  }
  EXPECT_EQ(n, kFrames);
  const cv::Mat png = cv::imread((d / "frame_000010.png").string());
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.at<cv::Vec3b>(10, 10), cv::Vec3b(40, 200, 200));  // lossless: exact BGR
  EXPECT_FALSE(fs::exists(d / "frame_000003.png"));
  EXPECT_EQ(thumbs.size(), 3u);
  fs::remove_all(d);
}

TEST(FrameRecorder, UnopenableVideoIsNamed) {
  FrameRecorderOptions o;
  o.video_path = "/nonexistent-dir/run.avi";
  try {
    FrameRecorder rec(64, 48, o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/run.avi"), std::string::npos);
  }
}

TEST(RunProgress, ALineEveryPeriodWithTheCountsSoFarAndNoBurstAfterAStall) {
  char buf[4096] = {};
  std::FILE* out = fmemopen(buf, sizeof buf - 1, "w");
  ASSERT_NE(out, nullptr);
  constexpr int64_t kStart = 5'000'000'000, kFrame = 10'000'000;  // 100 Hz
  RunProgress progress(1.0, out, kStart);
  uint64_t frames = 0;
  // 2.5 s of frames: video, then hybrid, then synthetic; every 50th misses.
  for (int i = 1; i <= 250; ++i) {
    const core::Variant v = i <= 100
                                ? core::Variant::kVideo
                                : (i <= 150 ? core::Variant::kHybrid : core::Variant::kSynthetic);
    progress.frame_done(v, ++frames, static_cast<uint64_t>(i / 50), kStart + i * kFrame);
  }
  // A 4 s stall: one line for it, not four.
  progress.frame_done(core::Variant::kSynthetic, ++frames, 5, kStart + 6'600'000'000);
  std::fclose(out);
  const std::string text(buf);
  std::vector<std::string> lines;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u) << text;
  EXPECT_EQ(lines[0].rfind("  [     1 s] frames 100, missed deadlines 2 (2.00 %); video 100 / "
                           "hybrid 0 / synthetic 0 frames; resident ",
                           0),
            0u)
      << lines[0];
  EXPECT_NE(
      lines[1].find("[     2 s] frames 200, missed deadlines 4 (2.00 %); video 100 / hybrid 50 "
                    "/ synthetic 50 frames"),
      std::string::npos)
      << lines[1];
  EXPECT_NE(
      lines[2].find("[     7 s] frames 251, missed deadlines 5 (1.99 %); video 100 / hybrid 50 "
                    "/ synthetic 101 frames"),
      std::string::npos)
      << lines[2];
  EXPECT_NE(lines[2].find(" MiB"), std::string::npos);
  // This test program's own resident memory: more than nothing, less than the machine.
  const long kib = RunProgress::resident_kib();
  EXPECT_GT(kib, 1024);
  EXPECT_LT(kib, 24L * 1024 * 1024);
}

TEST(RunProgress, ZeroPeriodPrintsNothing) {
  char buf[256] = {};
  std::FILE* out = fmemopen(buf, sizeof buf - 1, "w");
  ASSERT_NE(out, nullptr);
  RunProgress progress(0.0, out, 0);
  for (int i = 1; i <= 1000; ++i)
    progress.frame_done(core::Variant::kVideo, i, 0, i * 100'000'000LL);
  std::fclose(out);
  EXPECT_STREQ(buf, "");
}

}  // namespace
}  // namespace hd::station
