// The GL lens pass (the exact fragment pass) against the CPU table: the same eyes give the same
// panel within 2 levels, and features land within 1 px of each other.
#include <gtest/gtest.h>

#include <cmath>

#include "render/lens/cpu_predistorter.h"
#include "render/lens/hmd_profile_file.h"
#include "support/gl_vs_cpu_test.h"
#include "test_paths.h"

namespace hd::render::test {
namespace {

const std::string kDir = std::string(hd::test::source_dir()) + "/render/lens/profiles/";

// Smooth colour ramps (at most ~6 levels per px) with a dark blob every 64 px, different per
// channel so a channel mix-up shows.
ImageRgba8 eyes_picture(const lens::LensWarp& w) {
  ImageRgba8 img;
  img.allocate(2 * w.eye_width(), w.eye_height());
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double du = std::remainder(x + 0.5, 64.0), dv = std::remainder(y + 0.5, 64.0);
      const double blob = std::exp(-(du * du + dv * dv) / 18.0);
      uint8_t* p = img.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<uint8_t>(
            std::lround((1.0 - blob) * (127.5 + 100 * std::sin(0.02 * x + 0.015 * y + 2 * c))));
      p[3] = 255;
    }
  return img;
}

struct Comparison {
  int worst = 0;       // largest channel difference away from the rim
  int rim_pixels = 0;  // pixels within 1 px of the usable radius (either side may call them out)
};

Comparison compare(const lens::LensWarp& w, const ImageRgba8& a, const ImageRgba8& b) {
  Comparison r;
  const double max_r = w.profile().max_radius;
  // One panel pixel in r units (the larger axis), for "within 1 px of the rim".
  const double px_r = std::max(w.profile().pitch_x_m() / w.profile().r_unit_m.x(),
                               w.profile().pitch_y_m() / w.profile().r_unit_m.y());
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const int e = x < w.eye_panel_width() ? 0 : 1;
      if (max_r > 0 &&
          std::abs(w.radius(e, x - e * w.eye_panel_width() + 0.5, y + 0.5) - max_r) < px_r) {
        ++r.rim_pixels;
        continue;
      }
      for (int c = 0; c < 4; ++c) {
        const int d = std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c]));
        r.worst = std::max(r.worst, d);
      }
    }
  return r;
}

class GlLensTest : public GlVsCpuTest {
 protected:
  void run_both(const lens::LensWarp& w) {
    const ImageRgba8 eyes = eyes_picture(w);
    lens::CpuPredistorter cpu(w, 2);
    cpu_panel_.allocate(w.panel_width(), w.panel_height());
    gl_panel_.allocate(w.panel_width(), w.panel_height());
    ASSERT_TRUE(cpu.apply(eyes, cpu_panel_));
    gl_->set_lens(&w);
    gl_->load_picture(eyes);
    gl_->predistort(eyes, gl_panel_);
    gl_->set_lens(nullptr);
  }
  ImageRgba8 cpu_panel_, gl_panel_;
};

TEST_F(GlLensTest, OsvrWithChromaticAberrationAgreesWithTheCpuTable) {
  lens::HmdProfile p = lens::load_hmd_profile(kDir + "osvr-hdk-1.3.yaml");
  p.aberration = {0.985, 1.0, 1.015};  // the DK1's, so every channel has its own points
  const lens::LensWarp w(p);
  run_both(w);
  const Comparison c = compare(w, cpu_panel_, gl_panel_);
  EXPECT_LE(c.worst, 2);
  // The picture is not trivially equal: the lens moved things (centre pixel is not the corner's).
  EXPECT_NE(cpu_panel_.pixel(480, 540)[0], cpu_panel_.pixel(10, 10)[0]);
}

TEST_F(GlLensTest, Dk1WithItsRimAgreesWithTheCpuTable) {
  const lens::LensWarp w(lens::load_hmd_profile(kDir + "oculus-dk1.yaml"));
  run_both(w);
  const Comparison c = compare(w, cpu_panel_, gl_panel_);
  EXPECT_LE(c.worst, 2);
  EXPECT_LT(c.rim_pixels, 2 * 2 * 2 * 3.1416 * 1.15 * 368);  // a 2-px ring per eye, at most
  // Beyond the rim both are opaque black.
  EXPECT_EQ(gl_panel_.pixel(0, 0)[0], 0);
  EXPECT_EQ(gl_panel_.pixel(0, 0)[3], 255);
}

// Blob centres (the dark spots) found in both panels lie within 1 px of each other.
TEST_F(GlLensTest, FeaturesLandWithinOnePixel) {
  const lens::LensWarp w(lens::load_hmd_profile(kDir + "osvr-hdk-1.3.yaml"));
  run_both(w);
  int found = 0;
  double worst = 0;
  for (int by = 40; by < w.panel_height() - 40; by += 90)
    for (int bx = 40; bx < w.panel_width() - 40; bx += 90) {
      // Darkest pixel of the CPU panel near (bx, by), then both centroids of darkness around it.
      int mx = bx, my = by, mv = 1 << 30;
      for (int y = by - 30; y < by + 30; ++y)
        for (int x = bx - 30; x < bx + 30; ++x)
          if (cpu_panel_.pixel(x, y)[1] < mv) mv = cpu_panel_.pixel(x, y)[1], mx = x, my = y;
      if (mv > 10 || mx < 8 || my < 8 || mx > w.panel_width() - 8 || my > w.panel_height() - 8)
        continue;
      double c[2][3] = {};
      for (int k = 0; k < 2; ++k) {
        const ImageRgba8& img = k == 0 ? cpu_panel_ : gl_panel_;
        for (int y = my - 5; y <= my + 5; ++y)
          for (int x = mx - 5; x <= mx + 5; ++x) {
            const double d = 255.0 - img.pixel(x, y)[1];
            c[k][0] += d * x, c[k][1] += d * y, c[k][2] += d;
          }
      }
      worst = std::max(worst, std::hypot(c[0][0] / c[0][2] - c[1][0] / c[1][2],
                                         c[0][1] / c[0][2] - c[1][1] / c[1][2]));
      ++found;
    }
  EXPECT_GT(found, 40);
  EXPECT_LE(worst, 1.0);
}

}  // namespace
}  // namespace hd::render::test
