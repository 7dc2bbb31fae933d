// The CPU compositor's per-row kernels: the SSE2 versions give the scalar versions' bytes, and
// both give what the closed forms say (identity warps, pure video, pure model, full grey).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "render/compositor/border_weight.h"
#include "render/compositor/depth_warp.h"
#include "render/compositor/packed_rgba.h"
#include "render/compositor/row_kernels.h"

namespace {

using hd::render::RowBlend;
using hd::render::RowWarp;

uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

uint32_t pack(uint8_t r, uint8_t g, uint8_t b, uint8_t a) {
  return r | (uint32_t{g} << 8) | (uint32_t{b} << 16) | (uint32_t{a} << 24);
}

// A random projective row: mostly near the frame's edges so that rows cross them, sometimes
// anywhere (behind the eye, through h2 = 0, beyond the near plane).
RowWarp random_row_warp() {
  RowWarp w;
  auto coef = [](int lo, int hi, double scale) { return *rc::gen::inRange(lo, hi) * scale; };
  w.h00 = coef(-3000, 3000, 1e-3);
  w.h10 = coef(-1000, 1000, 1e-3);
  w.h20 = coef(-2000, 2000, 1e-6);
  w.q0 = coef(-2000, 2000, 1e-6);
  w.bw = coef(-200, 2000, 1e-3);
  w.bz = coef(-200, 30000, 1e-3);
  w.bx = *rc::gen::element(coef(-150, 150, 1.0), coef(1450, 1750, 1.0), coef(-4000, 4000, 1.0));
  w.by = *rc::gen::element(coef(-50, 50, 1.0), coef(1150, 1250, 1.0), coef(-300, 1500, 1.0));
  w.bx *= w.bw;  // so that u ~ bx / bw sits where it was drawn
  w.by *= w.bw;
  w.inv_near = 20.0;
  w.width = 1600;
  w.height = 1200;
  w.weight = static_cast<float>(*rc::gen::inRange(1, 1001) / 1000.0);
  return w;
}

RC_GTEST_PROP(RowKernels, Sse2AndAvxWarpRowsGiveTheScalarBitsForAnyHomography, ()) {
  const RowWarp w = random_row_warp();
  const int n = *rc::gen::inRange(0, 300);
  std::vector<float> u0(n), v0(n), a0(n), u1(n, -1.0f), v1(n, -1.0f), a1(n, -1.0f);
  std::vector<float> u2(n, -1.0f), v2(n, -1.0f), a2(n, -1.0f);
  hd::render::warp_row_scalar(w, n, u0.data(), v0.data(), a0.data());
  hd::render::warp_row_sse2(w, n, u1.data(), v1.data(), a1.data());
  hd::render::warp_row_avx(w, n, u2.data(), v2.data(), a2.data());
  int inside = 0;
  for (int x = 0; x < n; ++x) inside += a0[x] > 0.0f ? 1 : 0;
  RC_CLASSIFY(inside > 0 && inside < n, "row crosses the frame's edge");
  RC_CLASSIFY(inside == n && n > 0, "row inside the frame");
  for (int x = 0; x < n; ++x) {
    RC_ASSERT(bits(u0[x]) == bits(u1[x]));
    RC_ASSERT(bits(v0[x]) == bits(v1[x]));
    RC_ASSERT(bits(a0[x]) == bits(a1[x]));
    RC_ASSERT(bits(u0[x]) == bits(u2[x]));
    RC_ASSERT(bits(v0[x]) == bits(v2[x]));
    RC_ASSERT(bits(a0[x]) == bits(a2[x]));
  }
}

RC_GTEST_PROP(RowKernels, Sse2BorderWeightRowGivesTheScalarBits, ()) {
  const double w_video = *rc::gen::inRange(0, 1001) / 1000.0;
  const int width = *rc::gen::inRange(1, 2000), height = *rc::gen::inRange(1, 2000);
  const hd::render::BorderWeight border(w_video, width, height);
  const int n = *rc::gen::inRange(0, 40);
  std::vector<float> u(n), v(n), a(n);
  for (int x = 0; x < n; ++x) {
    // Anywhere in the frame, and often on its edges and centre lines (the case boundaries).
    u[x] = *rc::gen::element(0.0f, static_cast<float>(width), 0.5f * static_cast<float>(width),
                             static_cast<float>(*rc::gen::inRange(0, 1 << 16)) * width / 65536.0f);
    v[x] = *rc::gen::element(0.0f, static_cast<float>(height), 0.5f * static_cast<float>(height),
                             static_cast<float>(*rc::gen::inRange(0, 1 << 16)) * height / 65536.0f);
    a[x] = *rc::gen::element(0.0f, 0.5f, 1.0f);
  }
  std::vector<float> a0 = a, a1 = a;
  border.apply_row_scalar(n, u.data(), v.data(), a0.data());
  border.apply_row(n, u.data(), v.data(), a1.data());
  for (int x = 0; x < n; ++x) {
    RC_ASSERT(bits(a0[x]) == bits(a1[x]));
    if (a[x] == 0.0f) RC_ASSERT(a1[x] == 0.0f);  // no video there: stays none
  }
}

TEST(RowKernels, IdentityWarpSamplesAtThePixelCentresInsideTheFrameOnly) {
  // u = px, v = the row's centre 7.5, h2 = 1, 1/z = 1: the frame is 10 px wide, so x = 0..9 see
  // it at u = x + 0.5 and x >= 10 (u > 10) do not.
  RowWarp w;
  w.h00 = 1.0;
  w.by = 7.5;
  w.bw = 1.0;
  w.bz = 1.0;
  w.inv_near = 2.0;
  w.width = 10.0;
  w.height = 8.0;
  w.weight = 0.25f;
  const int n = 13;
  for (auto kernel :
       {&hd::render::warp_row_scalar, &hd::render::warp_row_sse2, &hd::render::warp_row_avx}) {
    std::vector<float> u(n, -1.0f), v(n, -1.0f), a(n, -1.0f);
    kernel(w, n, u.data(), v.data(), a.data());
    for (int x = 0; x < n; ++x) {
      const bool in = x < 10;
      EXPECT_EQ(u[x], in ? x + 0.5f : 0.0f) << x;
      EXPECT_EQ(v[x], in ? 7.5f : 0.0f) << x;
      EXPECT_EQ(a[x], in ? 0.25f : 0.0f) << x;
    }
  }
  // Behind the eye (1/z < 0) or nearer than the near plane (1/z > 1/near): no video anywhere.
  for (double bz : {-1.0, 2.5}) {
    w.bz = bz;
    std::vector<float> u(n), v(n), a(n, -1.0f);
    hd::render::warp_row_sse2(w, n, u.data(), v.data(), a.data());
    for (int x = 0; x < n; ++x) EXPECT_EQ(a[x], 0.0f) << "bz " << bz << " x " << x;
  }
}

RC_GTEST_PROP(RowKernels, Sse2BlendRowGivesTheScalarBytesForEveryMarking, ()) {
  const int n = *rc::gen::inRange(0, 40);
  const int style = *rc::gen::inRange(0, 3);  // none, desaturate, checker
  RowBlend b;
  b.background = pack(*rc::gen::arbitrary<uint8_t>(), *rc::gen::arbitrary<uint8_t>(),
                      *rc::gen::arbitrary<uint8_t>(), 255);
  b.desaturate = style == 1;
  b.desaturation = static_cast<float>(*rc::gen::inRange(0, 1001) / 1000.0);
  b.checker = style == 2;
  b.checker_step = static_cast<float>(*rc::gen::inRange(0, 2551) / 10.0);
  b.checker_cell_px = *rc::gen::inRange(1, 9);
  b.checker_row = *rc::gen::inRange(0, 5);
  const int x0 = *rc::gen::inRange(0, 9);
  const bool with_video = *rc::gen::arbitrary<bool>();
  std::vector<uint8_t> synth(4 * static_cast<std::size_t>(n));
  std::vector<float> depth(n), a(n);
  std::vector<uint32_t> video(n);
  for (int x = 0; x < n; ++x) {
    for (int c = 0; c < 4; ++c) synth[4 * x + c] = *rc::gen::arbitrary<uint8_t>();
    depth[x] = *rc::gen::element(0.0f, 0.5f, 2.0f);
    // Weights at the ends and anywhere between, as the border weight produces them.
    a[x] = *rc::gen::element(
        0.0f, 1.0f,
        static_cast<float>(*rc::gen::inRange(0, 1 << 20)) / static_cast<float>(1 << 20));
    video[x] = pack(*rc::gen::arbitrary<uint8_t>(), *rc::gen::arbitrary<uint8_t>(),
                    *rc::gen::arbitrary<uint8_t>(), 255);
  }
  std::vector<uint8_t> out0(4 * static_cast<std::size_t>(n), 1), out1(out0.size(), 2);
  const float* ap = with_video ? a.data() : nullptr;
  hd::render::blend_row_scalar(b, x0, n, synth.data(), depth.data(), ap, video.data(), out0.data());
  hd::render::blend_row_sse2(b, x0, n, synth.data(), depth.data(), ap, video.data(), out1.data());
  RC_ASSERT(out0 == out1);
}

TEST(RowKernels, BlendEndsAreExactlyTheVideoTheModelOrTheBackground) {
  const int n = 7;  // one SSE2 step and a scalar tail
  RowBlend b;
  b.background = pack(30, 32, 40, 255);
  std::vector<uint8_t> synth(4 * n);
  std::vector<float> depth(n), ones(n, 1.0f), zeros(n, 0.0f);
  std::vector<uint32_t> video(n);
  for (int x = 0; x < n; ++x) {
    for (int c = 0; c < 3; ++c) synth[4 * x + c] = static_cast<uint8_t>(37 * x + 11 * c);
    synth[4 * x + 3] = 7;  // the model's alpha is not the picture's
    depth[x] = (x % 3 == 0) ? 0.0f : 1.5f;
    video[x] = pack(static_cast<uint8_t>(200 - x), static_cast<uint8_t>(3 * x), 99, 255);
  }
  for (auto kernel : {&hd::render::blend_row_scalar, &hd::render::blend_row_sse2}) {
    std::vector<uint8_t> out(4 * n);
    kernel(b, 0, n, synth.data(), depth.data(), ones.data(), video.data(), out.data());
    for (int x = 0; x < n; ++x) {
      uint32_t o;
      std::memcpy(&o, out.data() + 4 * x, 4);
      EXPECT_EQ(o, video[x]) << x;  // a = 1: the video texel, alpha 255
    }
    for (const float* a :
         {static_cast<const float*>(zeros.data()), static_cast<const float*>(nullptr)}) {
      kernel(b, 0, n, synth.data(), depth.data(), a, video.data(), out.data());
      for (int x = 0; x < n; ++x) {
        const uint8_t expect[4] = {depth[x] > 0 ? synth[4 * x] : uint8_t{30},
                                   depth[x] > 0 ? synth[4 * x + 1] : uint8_t{32},
                                   depth[x] > 0 ? synth[4 * x + 2] : uint8_t{40}, 255};
        EXPECT_EQ(0, std::memcmp(out.data() + 4 * x, expect, 4)) << x;
      }
    }
  }
}

TEST(RowKernels, FullDesaturationIsTheRoundedRec601Grey) {
  RowBlend b;
  b.desaturate = true;
  b.desaturation = 1.0f;
  const int n = 5;
  const uint8_t rgb[n][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {10, 200, 90}, {255, 255, 255}};
  std::vector<uint8_t> synth(4 * n);
  std::vector<float> depth(n, 1.0f);
  std::vector<uint32_t> video(n, 0);
  for (int x = 0; x < n; ++x) std::memcpy(synth.data() + 4 * x, rgb[x], 3);
  std::vector<uint8_t> out(4 * n);
  hd::render::blend_row_sse2(b, 0, n, synth.data(), depth.data(), nullptr, video.data(),
                             out.data());
  for (int x = 0; x < n; ++x) {
    const double grey = 0.299 * rgb[x][0] + 0.587 * rgb[x][1] + 0.114 * rgb[x][2];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[4 * x + c], grey, 0.5 + 1e-4) << x << " " << c;
  }
}

RC_GTEST_PROP(RowKernels, BilinearRgbaIsTheNestedLerpsBitForBit, ()) {
  uint8_t texels[16];
  for (auto& t : texels) t = *rc::gen::arbitrary<uint8_t>();
  const int fx = *rc::gen::inRange(0, 256), fy = *rc::gen::inRange(0, 256);
  uint32_t c00, c10, c01, c11;
  std::memcpy(&c00, texels, 4);
  std::memcpy(&c10, texels + 4, 4);
  std::memcpy(&c01, texels + 8, 4);
  std::memcpy(&c11, texels + 12, 4);
  using hd::render::lerp_rgba;
  RC_ASSERT(hd::render::bilinear_rgba(texels, 8, fx, fy) ==
            lerp_rgba(lerp_rgba(c00, c10, fx), lerp_rgba(c01, c11, fx), fy));
}

TEST(RowKernels, LerpRgbaIsTheRoundedWeightedMeanOfEachChannel) {
  // Closed form per channel: round((a (256 - f) + b f) / 256), halves rounded up.
  for (int f : {0, 1, 77, 128, 255}) {
    for (int av : {0, 1, 100, 254, 255}) {
      for (int bv : {0, 3, 128, 255}) {
        const uint32_t a = pack(static_cast<uint8_t>(av), static_cast<uint8_t>(bv), 0, 255);
        const uint32_t b = pack(static_cast<uint8_t>(bv), static_cast<uint8_t>(av), 255, 0);
        const uint32_t r = hd::render::lerp_rgba(a, b, f);
        auto expect = [&](int x, int y) { return (x * (256 - f) + y * f + 128) >> 8; };
        EXPECT_EQ(static_cast<int>(r & 255u), expect(av, bv));
        EXPECT_EQ(static_cast<int>((r >> 8) & 255u), expect(bv, av));
        EXPECT_EQ(static_cast<int>((r >> 16) & 255u), expect(0, 255));
        EXPECT_EQ(static_cast<int>(r >> 24), expect(255, 0));
      }
    }
  }
}

}  // namespace

namespace {

// The model-depth row: the AVX loop gives the scalar reference's bits for random rows, with
// model depth, plane fallback, points behind either camera, outside the frame and NaN.
TEST(DepthWarpRow, AvxGivesTheScalarReferencesBits) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coef(-2.0, 2.0);
  std::uniform_real_distribution<float> depth(-0.2f, 3.0f);
  int shown = 0, tested = 0;
  for (int trial = 0; trial < 200; ++trial) {
    hd::render::DepthRow w;
    w.a00 = 400 + 50 * coef(rng);
    w.a10 = 20 * coef(rng);
    w.a20 = 0.05 * coef(rng);
    w.cx = 300 * coef(rng);
    w.cy = 240 + 100 * coef(rng);
    w.cw = 1 + 0.3 * coef(rng);
    w.b0 = 100 * coef(rng);
    w.b1 = 50 * coef(rng);
    w.b2 = 0.2 * coef(rng);
    w.q0 = 0.001 * coef(rng);
    w.bz = 0.5 + 0.3 * coef(rng);
    w.inv_near = 20.0;
    w.width = 640;
    w.height = 480;
    w.weight = 0.75f;
    const float seen_map = 1.0f;
    if (trial % 2) {
      w.seen = &seen_map;
      w.seen_width = w.seen_height = 1;
    }
    const int n = 37 + trial % 29;  // a tail after the vectors
    std::vector<float> iz(static_cast<std::size_t>(n));
    for (float& z : iz) z = std::max(0.0f, depth(rng));
    if (trial % 7 == 0) iz[3] = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> r1(4 * n), r2(4 * n);
    hd::render::depth_warp_row(w, n, iz.data(), r1.data(), r1.data() + n, r1.data() + 2 * n,
                               r1.data() + 3 * n);
    hd::render::depth_warp_row_scalar(w, n, iz.data(), r2.data(), r2.data() + n, r2.data() + 2 * n,
                                      r2.data() + 3 * n);
    ASSERT_EQ(std::memcmp(r1.data(), r2.data(), r1.size() * sizeof(float)), 0) << trial;
    for (int x = 0; x < n; ++x) {
      shown += r2[2 * n + x] > 0.0f;
      tested += r2[3 * n + x] > 0.0f;
    }
  }
  EXPECT_GT(shown, 100);  // the rows do reach the frame, and some await the seen test
  EXPECT_GT(tested, 50);
}

}  // namespace
