#pragma once
// CpuPredistorter's SIMD row kernels (x86-64: AVX2 + FMA, AVX-512 F/BW/VBMI): one row of one eye's
// usable span at a time, giving the same bytes as the scalar rows in cpu_predistorter.cpp (the
// same integer arithmetic as lens_sampler.h's sample_fixed). Each function is compiled for its
// instruction set alone (target attributes), so the caller checks cpu_has_avx2() /
// cpu_has_avx512() first. HD_LENS_AVX2 is 1 where they exist.

#include <cstdint>

#if defined(__x86_64__)
#define HD_LENS_AVX2 1
#endif

#if HD_LENS_AVX2
namespace hd::render::lens::kernels {

/// What the kRadial kernels need of one row and eye (CpuPredistorter::RadialEye's constants).
struct RadialArgs {
  const uint8_t* base;
  int stride;
  const float* ratio;
  int ratio_terms;
  float d0x, kx, dy, ry2;  // row constants: dy = float(y) + d0[1], ry2 = (dy * k[1])^2
  const float (*gain256)[2];
  const float* origin256;
  int x_lo, x_hi, y_hi;
};

/// AVX2 and FMA (cached).
bool cpu_has_avx2();
/// AVX-512 F, BW and VBMI besides AVX2 + FMA (cached).
bool cpu_has_avx512();

/// kPositionTable: panel pixels [x, end) of one row and eye, 8 at a time, from the green
/// positions `pos` of that row (R and B scaled about the principal point (CX, CY) by sr, sb in
/// 16.16); returns where it stopped (end - (end - x) % 8): the scalar row does the rest.
int table_span_avx2(const uint8_t* base, int stride, const int32_t* pos, uint32_t* out, int x,
                    int end, int CX, int CY, int32_t sr, int32_t sb, int x_lo, int x_hi, int y_hi);

/// kRadial: panel columns [x, end) of one row and eye (x - half_offset = the column in the
/// half), all of them (the last partial group is stored under a mask). `clamp` false: every
/// sample point is known to lie inside the eye (CpuPredistorter's clamp-free spans).
void radial_span_avx2(const RadialArgs& a, uint32_t* out, int x, int end, int half_offset,
                      bool clamp);
/// The same, 16 pixels per group (AVX-512 F, BW, VBMI).
void radial_span_avx512(const RadialArgs& a, uint32_t* out, int x, int end, int half_offset,
                        bool clamp);

}  // namespace hd::render::lens::kernels
#endif
