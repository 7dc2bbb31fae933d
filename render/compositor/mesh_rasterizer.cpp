#include "render/compositor/mesh_rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "render/compositor/packed_rgba.h"

namespace hd::render {

void MeshRasterizer::prepare(const SyntheticScene& scene, const core::Pinhole& eye,
                             const core::Pose& T_world_eye, double near_m, double far_m) {
  eye_ = eye;
  near_m_ = near_m;
  far_m_ = far_m;
  std::size_t total = 0;
  for (const auto& mesh : scene.meshes) total += mesh.positions_m.size();
  vertices_.resize(total);  // no allocation once the capacity has been reached
  mesh_base_.resize(scene.meshes.size());
  mesh_ok_.resize(scene.meshes.size());
  const Eigen::Matrix3d Rt = T_world_eye.R.transpose();
  std::size_t k = 0;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const auto& mesh = scene.meshes[m];
    mesh_base_[m] = k;
    mesh_ok_[m] = mesh.valid() ? 1 : 0;
    for (std::size_t i = 0; i < mesh.positions_m.size(); ++i, ++k) {
      const Eigen::Vector3d p = Rt * (mesh.positions_m[i].cast<double>() - T_world_eye.t);
      const Eigen::Vector2f uv = i < mesh.uvs.size() ? mesh.uvs[i] : Eigen::Vector2f::Zero();
      vertices_[k] = {p.x(), p.y(), p.z(), uv.x(), uv.y()};
    }
  }
}

void MeshRasterizer::draw_rows(const SyntheticScene& scene, const RasterTarget& target,
                               int row_begin, int row_end) const {
  for (std::size_t m = 0; m < scene.meshes.size() && m < mesh_ok_.size(); ++m) {
    if (!mesh_ok_[m]) continue;
    const auto& mesh = scene.meshes[m];
    const EyeVertex* base = vertices_.data() + mesh_base_[m];
    for (const auto& tri : mesh.triangles) {
      const EyeVertex v[3] = {base[tri[0]], base[tri[1]], base[tri[2]]};
      draw_triangle(mesh, v, target, row_begin, row_end);
    }
  }
}

namespace {

using Vertex = std::array<double, 5>;  // x, y, z, s, t in the eye frame
constexpr int kMaxPoly = 3 + 6;        // a triangle clipped by 6 planes
constexpr double kSubpixel = 256.0;    // vertices snap to 1/256 px, as GPUs do (llvmpipe too)
constexpr double kGuardPx = 8192.0;    // keeps fixed-point edge products far inside int64

// Sutherland–Hodgman against one plane a*x + b*y + c*z + d >= 0 (eye frame).
int clip(const Vertex* in, int n, Vertex* out, double a, double b, double c, double d) {
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const Vertex& p = in[i];
    const Vertex& q = in[(i + 1) % n];
    const double dp = a * p[0] + b * p[1] + c * p[2] + d;
    const double dq = a * q[0] + b * q[1] + c * q[2] + d;
    if (dp >= 0) out[count++] = p;
    if ((dp >= 0) != (dq >= 0)) {
      const double f = dp / (dp - dq);
      Vertex r;
      for (int j = 0; j < 5; ++j) r[j] = p[j] + f * (q[j] - p[j]);
      out[count++] = r;
    }
  }
  return count;
}

}  // namespace

void MeshRasterizer::draw_triangle(const TexturedMesh& mesh, const EyeVertex* v,
                                   const RasterTarget& target, int row_begin, int row_end) const {
  Vertex pa[kMaxPoly];
  Vertex pb[kMaxPoly];
  for (int i = 0; i < 3; ++i) pa[i] = {v[i].x, v[i].y, v[i].z, v[i].s, v[i].t};
  // Near and far planes, then a guard band around the image (u, v in [-G, size + G]) so that
  // projected coordinates stay small; the guard band never changes which pixels are covered.
  const double fx = eye_.fx, fy = eye_.fy, cx = eye_.cx, cy = eye_.cy;
  const double W = target.width, H = target.height;
  int n = clip(pa, 3, pb, 0, 0, 1, -near_m_);
  n = n < 3 ? 0 : clip(pb, n, pa, 0, 0, -1, far_m_);
  n = n < 3 ? 0 : clip(pa, n, pb, fx, 0, cx + kGuardPx, 0);       // u >= -G
  n = n < 3 ? 0 : clip(pb, n, pa, -fx, 0, W + kGuardPx - cx, 0);  // u <= W + G
  n = n < 3 ? 0 : clip(pa, n, pb, 0, fy, cy + kGuardPx, 0);       // v >= -G
  n = n < 3 ? 0 : clip(pb, n, pa, 0, -fy, H + kGuardPx - cy, 0);  // v <= H + G
  if (n < 3) return;

  // Screen position (fixed point) plus the attributes linear in screen space: 1/z, s/z, t/z.
  struct Screen {
    int64_t X, Y;
    double iz, sz, tz;
  };
  Screen sc[kMaxPoly];
  for (int i = 0; i < n; ++i) {
    const double iz = 1.0 / pa[i][2];
    const double u = fx * pa[i][0] * iz + cx;
    const double w = fy * pa[i][1] * iz + cy;
    sc[i] = {std::llround(u * kSubpixel), std::llround(w * kSubpixel), iz, pa[i][3] * iz,
             pa[i][4] * iz};
  }

  const auto& tex = mesh.texture;
  const auto sub = static_cast<int64_t>(kSubpixel);
  for (int k = 1; k + 1 < n; ++k) {
    Screen p0 = sc[0], p1 = sc[k], p2 = sc[k + 1];
    int64_t area = (p1.X - p0.X) * (p2.Y - p0.Y) - (p1.Y - p0.Y) * (p2.X - p0.X);
    if (area == 0) continue;
    if (area < 0) {
      std::swap(p1, p2);
      area = -area;
    }
    const int64_t min_x = std::min({p0.X, p1.X, p2.X}), max_x = std::max({p0.X, p1.X, p2.X});
    const int64_t min_y = std::min({p0.Y, p1.Y, p2.Y}), max_y = std::max({p0.Y, p1.Y, p2.Y});
    // Pixel x is a candidate when its centre (x + 0.5) * sub lies in [min_x, max_x].
    auto first_px = [&](int64_t lo) {
      return static_cast<int>(std::ceil((static_cast<double>(lo) / kSubpixel) - 0.5));
    };
    auto last_px = [&](int64_t hi) {
      return static_cast<int>(std::floor((static_cast<double>(hi) / kSubpixel) - 0.5));
    };
    const int x0 = std::max(first_px(min_x), 0);
    const int x1 = std::min(last_px(max_x), target.width - 1);
    const int y0 = std::max(first_px(min_y), row_begin);
    const int y1 = std::min(last_px(max_y), row_end - 1);
    if (x0 > x1 || y0 > y1) continue;

    // Edge e runs from a to b; E_e(p) = (b - a) x (p - a) > 0 inside (area > 0, y down). Edge 0
    // is opposite p0, edge 1 opposite p1, edge 2 opposite p2, so E_e / area are barycentrics.
    const Screen* ea[3] = {&p1, &p2, &p0};
    const Screen* eb[3] = {&p2, &p0, &p1};
    int64_t dX[3], dY[3], tl[3];
    for (int e = 0; e < 3; ++e) {
      dX[e] = eb[e]->X - ea[e]->X;
      dY[e] = eb[e]->Y - ea[e]->Y;
      // Top-left rule with y down: a left edge goes up (dY < 0), a top edge goes right (dY = 0,
      // dX > 0). A centre exactly on another edge belongs to the neighbouring triangle.
      tl[e] = (dY[e] < 0 || (dY[e] == 0 && dX[e] > 0)) ? 1 : 0;
    }
    const double inv_area = 1.0 / static_cast<double>(area);
    // Attributes a = l0 a0 + l1 a1 + l2 a2 with l_e = E_e / area: one step in x changes E_e by
    // -dY_e * sub, so each attribute changes by a constant per pixel.
    auto step_of = [&](double a0, double a1, double a2) {
      return -(static_cast<double>(dY[0]) * a0 + static_cast<double>(dY[1]) * a1 +
               static_cast<double>(dY[2]) * a2) *
             static_cast<double>(sub) * inv_area;
    };
    const double diz = step_of(p0.iz, p1.iz, p2.iz);
    const double dsz = step_of(p0.sz, p1.sz, p2.sz);
    const double dtz = step_of(p0.tz, p1.tz, p2.tz);
    const float tex_w = static_cast<float>(tex.width), tex_h = static_cast<float>(tex.height);
    const uint8_t* tdata = tex.data.data();
    for (int y = y0; y <= y1; ++y) {
      const int64_t PY = y * sub + sub / 2;
      const int64_t PX = x0 * sub + sub / 2;
      uint8_t* rgba_row =
          target.rgba ? target.rgba + static_cast<long>(y) * target.width * 4 : nullptr;
      float* depth_row = target.inv_depth + static_cast<long>(y) * target.width;
      int64_t E[3];
      for (int e = 0; e < 3; ++e) E[e] = dX[e] * (PY - ea[e]->Y) - dY[e] * (PX - ea[e]->X);
      // The covered span of this row, exactly: E_e(x0 + i) = E_e + k_e i with k_e = -dY_e sub,
      // covered while E_e + k_e i + tl_e > 0 for all three edges.
      int64_t i_lo = 0, i_hi = x1 - x0;
      for (int e = 0; e < 3; ++e) {
        const int64_t k = -dY[e] * sub;
        const int64_t c0 = E[e] + tl[e];  // covered iff c0 + k i > 0
        if (k == 0) {
          if (c0 <= 0) i_hi = -1;
        } else if (k > 0) {
          // i > -c0 / k  ->  i >= floor(-c0 / k) + 1
          const int64_t n = -c0;
          const int64_t fl = n >= 0 ? n / k : -((-n + k - 1) / k);
          i_lo = std::max(i_lo, fl + 1);
        } else {
          // i < c0 / (-k)  ->  i <= ceil(c0 / (-k)) - 1
          const int64_t m = -k;
          const int64_t ce = c0 >= 0 ? (c0 + m - 1) / m : -((-c0) / m);
          i_hi = std::min(i_hi, ce - 1);
        }
      }
      if (i_lo > i_hi) continue;
      const int xs = x0 + static_cast<int>(i_lo), xe = x0 + static_cast<int>(i_hi);
      const double l0 = static_cast<double>(E[0]) * inv_area;
      const double l1 = static_cast<double>(E[1]) * inv_area;
      const double l2 = static_cast<double>(E[2]) * inv_area;
      const double di = static_cast<double>(i_lo);
      double iz = l0 * p0.iz + l1 * p1.iz + l2 * p2.iz + di * diz;
      double sz = l0 * p0.sz + l1 * p1.sz + l2 * p2.sz + di * dsz;
      double tz = l0 * p0.tz + l1 * p1.tz + l2 * p2.tz + di * dtz;
      for (int x = xs; x <= xe; ++x, iz += diz, sz += dsz, tz += dtz) {
        const float izf = static_cast<float>(iz);
        if (izf > depth_row[x]) {
          depth_row[x] = izf;
          if (rgba_row == nullptr) continue;  // a depth map only
          const double z = 1.0 / iz;
          // Texel position, clamped so the fixed-point conversion below stays positive.
          const float tu = std::clamp(static_cast<float>(sz * z) * tex_w, -1.0f, tex_w + 1.0f);
          const float tv = std::clamp(static_cast<float>(tz * z) * tex_h, -1.0f, tex_h + 1.0f);
          // round((t - 0.5) * 256) as floor(t * 256 - 127.5), made positive by +512.
          const int X = static_cast<int>(tu * 256.0f + 384.5f) - 512;
          const int Y = static_cast<int>(tv * 256.0f + 384.5f) - 512;
          if (static_cast<unsigned>(X >> 8) < static_cast<unsigned>(tex.width - 1) &&
              static_cast<unsigned>(Y >> 8) < static_cast<unsigned>(tex.height - 1)) {
            // All four texels inside: the SSE2 bilinear, bit-identical to the lerps below.
            const uint32_t c =
                bilinear_rgba(tdata + static_cast<long>(Y >> 8) * tex.stride_bytes + 4 * (X >> 8),
                              tex.stride_bytes, X & 255, Y & 255) |
                0xFF000000u;
            std::memcpy(rgba_row + 4 * x, &c, 4);
            continue;
          }
          const int xa = std::clamp(X >> 8, 0, tex.width - 1);
          const int xb = std::clamp((X >> 8) + 1, 0, tex.width - 1);
          const int ya = std::clamp(Y >> 8, 0, tex.height - 1);
          const int yb = std::clamp((Y >> 8) + 1, 0, tex.height - 1);
          const uint8_t* r0 = tdata + static_cast<long>(ya) * tex.stride_bytes;
          const uint8_t* r1 = tdata + static_cast<long>(yb) * tex.stride_bytes;
          uint32_t c00, c10, c01, c11;
          std::memcpy(&c00, r0 + 4 * xa, 4);
          std::memcpy(&c10, r0 + 4 * xb, 4);
          std::memcpy(&c01, r1 + 4 * xa, 4);
          std::memcpy(&c11, r1 + 4 * xb, 4);
          const uint32_t c =
              lerp_rgba(lerp_rgba(c00, c10, X & 255), lerp_rgba(c01, c11, X & 255), Y & 255) |
              0xFF000000u;
          std::memcpy(rgba_row + 4 * x, &c, 4);
        }
      }
    }
  }
}

}  // namespace hd::render
