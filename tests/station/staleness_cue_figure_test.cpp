// The continuous staleness cue (issue 11 item 2) drawn by the station's own CPU compositor at
// three ages, as docs/staleness_cue.png shows it: a fresh model and fresh video look exactly as
// without the cue; an aging model is pulled toward grey in proportion to its age; video past its
// warning bound gets a frame in the stale colour. The picture is written to the build folder
// (copied to docs/ by hand when the cue changes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/marking.h"
#include "render/compositor/cpu_compositor.h"
#include "render/compositor/demo_scene.h"

namespace hd::render {
namespace {

constexpr int kW = 320, kH = 240;

struct Case {
  const char* label;
  double model_age_ms;
  double video_age_ms;
  bool video_stale;
};

// One hybrid frame (half video, half model by the global blend) with the marking for the ages.
ImageRgba8 draw(const SyntheticScene& scene, const drivers::Frame& video,
                const core::MarkingParams& marking) {
  CompositeRequest req;
  req.scene = &scene;
  req.eye = core::Pinhole::centred(260, kW, kH);
  req.T_world_eye = core::Pose::identity();
  req.T_world_eye.t = {0.12, 0.0, 0.0};
  req.video = &video;
  req.real = core::Pinhole::centred(260, kW, kH);
  req.T_world_real = core::Pose::identity();
  req.d_m = 2.2;
  req.region = {0, 0, kW, kH};
  req.has_region = true;
  req.transition = {core::Variant::kHybrid, 0.5, 0.5};
  req.mode = core::TransitionMode::kGlobalBlend;
  req.marking = marking;
  req.viewport = {0, 0, kW, kH};
  ImageRgba8 out;
  out.allocate(kW, kH);
  CpuCompositor compositor(1);
  compositor.draw(req, out);
  return out;
}

// Mean distance of the picture's channels from mid-grey (128).
double contrast(const ImageRgba8& img) {
  double sum = 0.0;
  for (int y = 16; y < kH - 16; ++y)
    for (int x = 16; x < kW - 16; ++x)
      for (int c = 0; c < 3; ++c) sum += std::abs(img.pixel(x, y)[c] - 128.0);
  return sum / (3.0 * (kW - 32) * (kH - 32));
}

TEST(StalenessCueFigure, FreshLooksAsBeforeAgingFadesStaleVideoIsFramed) {
  const SyntheticScene scene = make_demo_scene();
  drivers::Frame video;
  render_demo_frame(scene, core::Pinhole::centred(260, kW, kH), core::Pose::identity(), 40, video);
  core::MarkingParams base;
  base.style = core::MarkingStyle::kDesaturate;
  base.synthetic_desaturation = 1.0;

  const Case cases[] = {{"model 0.8 s, video 30 ms", 800.0, 30.0, false},
                        {"model 6 s, video 40 ms", 6000.0, 40.0, false},
                        {"model 12 s, video 110 ms", 12000.0, 110.0, true}};
  ImageRgba8 tiles[3];
  for (int i = 0; i < 3; ++i)
    tiles[i] = draw(scene, video, base.for_ages(cases[i].model_age_ms, cases[i].video_stale));

  // Fresh: bit for bit the picture without the cue.
  const ImageRgba8 plain = draw(scene, video, base);
  EXPECT_EQ(std::memcmp(plain.data.data(), tiles[0].data.data(), plain.data.size()), 0);
  // Aging: halfway between fresh (2 s) and full (10 s), the model's half of the blend moves
  // 0.5 * 0.6 of the way to grey: less contrast, but not the stale tile's even less.
  EXPECT_LT(contrast(tiles[1]), contrast(tiles[0]));
  EXPECT_LT(contrast(tiles[2]), contrast(tiles[1]));
  // Stale video: the stale colour all around, none of it in the fresh tiles.
  const core::Rgb& sc = base.stale_rgb;
  for (const auto& [x, y] : {std::pair{0, 0}, {kW - 1, kH / 2}, {kW / 2, kH - 1}, {3, 100}}) {
    const uint8_t* p = tiles[2].pixel(x, y);
    EXPECT_EQ(p[0], sc.r);
    EXPECT_EQ(p[1], sc.g);
    EXPECT_EQ(p[2], sc.b);
    EXPECT_NE(tiles[1].pixel(x, y)[1], sc.g);
  }

  // The figure: three tiles side by side, each labelled with its ages.
  cv::Mat sheet(kH + 28, 3 * kW + 8, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int i = 0; i < 3; ++i) {
    const cv::Mat rgba(kH, kW, CV_8UC4, tiles[i].data.data(),
                       static_cast<std::size_t>(tiles[i].stride_bytes));
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    bgr.copyTo(sheet(cv::Rect(i * (kW + 4), 0, kW, kH)));
    cv::putText(sheet, cases[i].label, {i * (kW + 4) + 6, kH + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  const std::string path = (std::filesystem::current_path() / "staleness_cue.png").string();
  ASSERT_TRUE(cv::imwrite(path, sheet)) << path;
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace
}  // namespace hd::render
