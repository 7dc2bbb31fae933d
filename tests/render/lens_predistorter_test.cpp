// The CPU pre-distortion: its table against the per-pixel evaluation, and pre-distortion
// followed by the lens (the closed form, written out here) giving back the eye image.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "core/allocation_counter.h"
#include "render/lens/cpu_predistorter.h"
#include "render/lens/hmd_profile_file.h"
#include "test_paths.h"

namespace hd::render::lens {
namespace {

const std::string kDir = std::string(hd::test::source_dir()) + "/render/lens/profiles/";

// The OSVR HDK 1.3's lens, independently of LensWarp: panel point (x, y) of eye e (half
// coordinates, px) -> where the eye sees it, in eye-image px relative to the principal point.
// At the centre one eye pixel is one panel pixel, so panel px and eye px share a scale there.
Eigen::Vector2d osvr_lens(int e, double x, double y) {
  const double cx = (e == 0 ? 0.471 : 0.529) * 960, cy = 0.5 * 1080;
  const double nx = (x - cx) / 960, ny = (y - cy) / 1080;
  const double r = std::hypot(nx, ny);
  const double k[6] = {0, 1, -1.74, 5.15, -1.27, -2.23};
  double p = 0;
  for (int i = 5; i >= 0; --i) p = p * r + k[i];
  const double s = r > 0 ? p / r : 1.0;
  return {s * (x - cx), s * (y - cy)};
}

// Two eye images of blobs (a Gaussian of sigma 1.5 px, one per grid node) or lines.
ImageRgba8 eyes_picture(const LensWarp& w, bool lines) {
  ImageRgba8 img;
  img.allocate(2 * w.eye_width(), w.eye_height());
  for (int e = 0; e < 2; ++e) {
    const core::Pinhole& k = w.eye(e);
    for (int y = 0; y < w.eye_height(); ++y)
      for (int x = 0; x < w.eye_width(); ++x) {
        const double u = x + 0.5 - k.cx, v = y + 0.5 - k.cy;
        double val = 0;
        if (lines) {
          const double du = std::remainder(u, 80.0), dv = std::remainder(v, 80.0);
          val = std::max(std::exp(-du * du / 4.5), std::exp(-dv * dv / 4.5));
        } else {
          const double du = std::remainder(u, 60.0), dv = std::remainder(v, 60.0);
          val = std::exp(-(du * du + dv * dv) / 4.5);
        }
        uint8_t* p = img.pixel(e * w.eye_width() + x, y);
        p[0] = p[1] = p[2] = static_cast<uint8_t>(std::lround(std::min(1.0, val) * 255));
        p[3] = 255;
      }
  }
  return img;
}

TEST(CpuPredistorter, TableMatchesPerPixelEvaluation) {
  const LensWarp w(load_hmd_profile(kDir + "oculus-dk1.yaml"));
  CpuPredistorter pd(w, 2);
  const ImageRgba8 eyes = eyes_picture(w, true);
  ImageRgba8 a, b;
  a.allocate(w.panel_width(), w.panel_height());
  b.allocate(w.panel_width(), w.panel_height());
  ASSERT_TRUE(pd.apply(eyes, a));
  ASSERT_TRUE(pd.apply_exact(eyes, b));
  int worst = 0;
  for (std::size_t i = 0; i < a.data.size(); ++i)
    worst = std::max(worst, std::abs(int(a.data[i]) - int(b.data[i])));
  EXPECT_LE(worst, 1);
  // Beyond the usable radius (the DK1's panel corners) the panel is opaque black.
  EXPECT_EQ(a.pixel(0, 0)[0], 0);
  EXPECT_EQ(a.pixel(0, 0)[3], 255);
}

// The single-precision evaluation from the radius (the default) against LensWarp's double
// precision, every usable pixel and channel of two profiles; the first version's table of
// 1/256 px green positions is held to the 0.01 px plus its grid.
TEST(CpuPredistorter, SamplePointsMatchTheLensModel) {
  for (const char* name : {"osvr-hdk-1.3.yaml", "oculus-dk1.yaml"}) {
    HmdProfile p = load_hmd_profile(kDir + name);
    p.aberration = {0.985, 1.0, 1.015};
    const LensWarp w(p);
    const CpuPredistorter radial(w, 1),
        table(w, 1, CpuPredistorter::Simd::kBest, CpuPredistorter::Method::kPositionTable);
    double worst_radial = 0, worst_table = 0;
    int n = 0;
    for (int e = 0; e < 2; ++e)
      for (int y = 0; y < w.panel_height(); y += 3)
        for (int x = 0; x < w.eye_panel_width(); ++x)
          for (int c = 0; c < 3; ++c) {
            double u = 0, v = 0, pu = 0, pv = 0;
            if (!w.source(e, x + 0.5, y + 0.5, c, &u, &v)) break;
            radial.sample_point(e, x, y, c, &pu, &pv);
            worst_radial = std::max(worst_radial, std::hypot(pu - u, pv - v));
            table.sample_point(e, x, y, c, &pu, &pv);
            worst_table = std::max(worst_table, std::hypot(pu - u, pv - v));
            ++n;
          }
    EXPECT_GT(n, 100000) << name;
    EXPECT_LE(worst_radial, 0.001) << name;
    EXPECT_LE(worst_table, 0.01 + std::sqrt(2.0) / 256) << name;
  }
}

// Every kernel this CPU has (AVX2, and AVX-512 for kRadial), 1, 2 and 3 threads, against the
// scalar rows; the OSVR profile's spans run without the clamp, the DK1's rim spans (cut by its
// usable radius) with it.
TEST(CpuPredistorter, RowKernelGivesTheScalarBytes) {
  using Simd = CpuPredistorter::Simd;
  int clamp_free = 0, clamped = 0;
  for (const char* name : {"osvr-hdk-1.3.yaml", "oculus-dk1.yaml"}) {
    HmdProfile p = load_hmd_profile(kDir + name);
    p.aberration = {0.985, 1.0, 1.015};  // R and B off green: every path of the kernels
    const LensWarp w(p);
    const ImageRgba8 eyes = eyes_picture(w, true);
    ImageRgba8 a, b;
    a.allocate(w.panel_width(), w.panel_height());
    b.allocate(w.panel_width(), w.panel_height());
    for (const auto method :
         {CpuPredistorter::Method::kRadial, CpuPredistorter::Method::kPositionTable}) {
      CpuPredistorter scalar(w, 1, Simd::kNone, method);
      ASSERT_EQ(scalar.simd(), Simd::kNone);
      ASSERT_TRUE(scalar.apply(eyes, b));
      if (method == CpuPredistorter::Method::kRadial) {
        clamp_free += scalar.clamp_free_spans();
        clamped += 2 * w.panel_height() - scalar.clamp_free_spans();
      }
      for (const Simd level : {Simd::kAvx2, Simd::kBest})
        for (int threads : {1, 2, 3}) {
          CpuPredistorter simd(w, threads, level, method);
          std::fill(a.data.begin(), a.data.end(), 0);
          ASSERT_TRUE(simd.apply(eyes, a));
          EXPECT_EQ(a.data, b.data)
              << name << ", method " << static_cast<int>(method) << ", kernel "
              << static_cast<int>(simd.simd()) << ", threads " << threads;
        }
    }
  }
  EXPECT_GT(clamp_free, 100);
  EXPECT_GT(clamped, 100);
}

TEST(CpuPredistorter, ApplyAllocatesNothingAndRefusesWrongSizes) {
  const LensWarp w(load_hmd_profile(kDir + "osvr-hdk-1.3.yaml"));
  CpuPredistorter pd(w, 2);
  const ImageRgba8 eyes = eyes_picture(w, false);
  ImageRgba8 panel;
  panel.allocate(w.panel_width(), w.panel_height());
  ASSERT_TRUE(pd.apply(eyes, panel));
  core::reset_counted_allocations();
  core::count_allocations_on_all_threads(true);
  const bool ok = pd.apply(eyes, panel);
  core::count_allocations_on_all_threads(false);
  EXPECT_TRUE(ok);
  EXPECT_EQ(core::counted_allocations(), 0u);
  ImageRgba8 small;
  small.allocate(10, 10);
  EXPECT_FALSE(pd.apply(small, panel));
  EXPECT_FALSE(pd.apply(eyes, small));
}

// Finds each blob in the panel (per channel, intensity-weighted centroid), passes it through the
// lens and compares with where the blob is in the eye image.
TEST(CpuPredistorter, PredistortionThenLensGivesBackTheEyeImage) {
  const LensWarp w(load_hmd_profile(kDir + "osvr-hdk-1.3.yaml"));
  CpuPredistorter pd(w, 1);
  const ImageRgba8 eyes = eyes_picture(w, false);
  ImageRgba8 panel;
  panel.allocate(w.panel_width(), w.panel_height());
  ASSERT_TRUE(pd.apply(eyes, panel));
  int found = 0;
  double worst = 0;
  for (int e = 0; e < 2; ++e) {
    for (int gy = -6; gy <= 6; ++gy)
      for (int gx = -6; gx <= 6; ++gx) {
        const Eigen::Vector2d want(60.0 * gx, 60.0 * gy);  // blob centre, eye px from centre
        // Its panel position: invert the closed-form lens by Newton steps from the centre.
        const double pcx = (e == 0 ? 0.471 : 0.529) * 960, pcy = 540;
        Eigen::Vector2d p(pcx + want.x(), pcy + want.y());
        for (int it = 0; it < 60; ++it) {
          const Eigen::Vector2d f = osvr_lens(e, p.x(), p.y()) - want;
          const double h = 1e-4;
          Eigen::Matrix2d J;
          J.col(0) = (osvr_lens(e, p.x() + h, p.y()) - osvr_lens(e, p.x() - h, p.y())) / (2 * h);
          J.col(1) = (osvr_lens(e, p.x(), p.y() + h) - osvr_lens(e, p.x(), p.y() - h)) / (2 * h);
          p -= J.inverse() * f;
        }
        if (p.x() < 8 || p.x() > 952 || p.y() < 8 || p.y() > 1072) continue;
        // Centroid in a 9x9 window of the panel around that guess.
        double sx = 0, sy = 0, sw = 0;
        const int x0 = static_cast<int>(p.x()), y0 = static_cast<int>(p.y());
        for (int y = y0 - 4; y <= y0 + 4; ++y)
          for (int x = x0 - 4; x <= x0 + 4; ++x) {
            const double v = panel.pixel(e * 960 + x, y)[1];
            sx += v * (x + 0.5), sy += v * (y + 0.5), sw += v;
          }
        ASSERT_GT(sw, 0);
        const Eigen::Vector2d seen = osvr_lens(e, sx / sw, sy / sw);
        worst = std::max(worst, (seen - want).norm());
        ++found;
      }
  }
  EXPECT_GT(found, 150);
  EXPECT_LE(worst, 0.5);
}

// A straight grid of lines in the eye image, pre-distorted (visibly bent on the panel), then
// passed through the lens: every line is straight again and where it was.
TEST(CpuPredistorter, StraightGridIsStraightAgainThroughTheLens) {
  const LensWarp w(load_hmd_profile(kDir + "osvr-hdk-1.3.yaml"));
  CpuPredistorter pd(w, 2);
  const ImageRgba8 eyes = eyes_picture(w, true);
  ImageRgba8 panel;
  panel.allocate(w.panel_width(), w.panel_height());
  ASSERT_TRUE(pd.apply(eyes, panel));
  // The vertical line 160 px right of eye 0's centre: on each panel row, its crossing.
  double worst = 0, bend = 0, first_x = -1;
  int rows = 0;
  for (int y = 100; y < 980; y += 10) {
    // Where the lens says the line crosses this row (bisection), then the measured centroid.
    double lo = 452, hi = 952;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (osvr_lens(0, mid, y + 0.5).x() < 160.0 ? lo : hi) = mid;
    }
    if (std::abs(std::remainder(osvr_lens(0, lo, y + 0.5).y(), 80.0)) < 8.0) continue;
    const int bx = static_cast<int>(lo);
    double sx = 0, sw = 0;
    for (int x = bx - 4; x <= bx + 4; ++x) {
      const double v = panel.pixel(x, y)[1];
      sx += v * (x + 0.5), sw += v;
    }
    ASSERT_GT(sw, 0);
    const double x_panel = sx / sw;
    if (first_x < 0) first_x = x_panel;
    bend = std::max(bend, std::abs(x_panel - first_x));
    worst = std::max(worst, std::abs(osvr_lens(0, x_panel, y + 0.5).x() - 160.0));
    ++rows;
  }
  EXPECT_GT(rows, 50);
  EXPECT_GT(bend, 5.0);   // on the panel the line is curved ...
  EXPECT_LE(worst, 0.5);  // ... and through the lens straight, at u = 160 px
}

}  // namespace
}  // namespace hd::render::lens
