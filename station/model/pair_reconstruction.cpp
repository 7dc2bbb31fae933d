#include "station/model/pair_reconstruction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "recon/stereo_image.h"
#include "render/compositor/mesh_rasterizer.h"

namespace hd::station {
namespace {

recon::StereoRig make_rig(const core::Pinhole& left, const core::Pose& T_left,
                          const core::Pinhole& right, const core::Pose& T_right) {
  recon::StereoRig rig;
  rig.left = left;
  rig.right = right;
  rig.T_world_left = T_left;
  rig.T_world_right = T_right;
  return rig;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

PairReconstruction::PairReconstruction(const ModelStereoPair& pair, const core::Pinhole& left_p_c,
                                       const core::Pose& T_world_left,
                                       const core::Pinhole& right_p_c,
                                       const core::Pose& T_world_right,
                                       const render::SyntheticScene& prior)
    : pair_(pair),
      left_p_c_(left_p_c),
      T_world_left_(T_world_left),
      recon_(make_rig(left_p_c, T_world_left, right_p_c, T_world_right), pair.reconstruction) {
  if (pair_.every_updates < 1)
    throw std::invalid_argument("stereo pair " + pair_.name + ": every_updates must be >= 1");
  if (!(pair_.prior_margin_px >= 0) || !(pair_.prior_margin_m >= 0))
    throw std::invalid_argument("stereo pair " + pair_.name + ": prior margins must be >= 0");
  // The a-priori depth along every left pixel, once: that geometry never moves.
  const int w = left_p_c_.width, h = left_p_c_.height;
  const cv::Size rs = recon_.rectification().size();
  const int stride = std::max(1, pair_.reconstruction.mesh.stride_px);
  max_vertices_ = static_cast<std::size_t>(rs.width / stride + 2) *
                  static_cast<std::size_t>(rs.height / stride + 2);
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  prior_inv_depth_.assign(n, 0.0f);
  std::vector<uint8_t> rgba(n * 4);
  render::MeshRasterizer raster;
  raster.prepare(prior, left_p_c_, T_world_left_, 0.05, 100.0);
  raster.draw_rows(prior, render::RasterTarget{rgba.data(), prior_inv_depth_.data(), w, h}, 0, h);
}

bool PairReconstruction::update(const drivers::Frame& left, const drivers::Frame& right) {
  const auto t0 = std::chrono::steady_clock::now();
  recon_.reconstruct(recon::stereo_image(left), recon::stereo_image(right), out_);
  stats_ = PairReconstructionStats{};
  stats_.status = out_.status;
  stats_.message = out_.message;
  stats_.reconstruct_ms = ms_since(t0);
  if (out_.status != recon::PairStatus::kOk && out_.status != recon::PairStatus::kNoValidDisparity)
    return false;  // refused: the previous mesh (and its age) stays
  capture_ns_ = out_.stats.capture_ns;
  const auto t1 = std::chrono::steady_clock::now();
  cut(left);
  stats_.cut_ms = ms_since(t1);
  return true;
}

void PairReconstruction::cut(const drivers::Frame& left) {
  const recon::DepthMesh& dm = out_.mesh;
  mesh_.positions_m.clear();
  mesh_.uvs.clear();
  mesh_.triangles.clear();
  stats_.vertices_measured = dm.positions_m.size();
  const int w = left_p_c_.width, h = left_p_c_.height;
  const Eigen::Matrix3d Rt = T_world_left_.R.transpose();
  const double fB = recon_.rectification().depth_m(1.0);  // f B: z = f B / d
  is_new_.assign(dm.positions_m.size(), 0);
  for (std::size_t i = 0; i < dm.positions_m.size(); ++i) {
    const Eigen::Vector3d X = dm.positions_m[i].cast<double>();
    if (pair_.use_bounds && !((X.array() >= pair_.bounds.min_m.array()).all() &&
                              (X.array() <= pair_.bounds.max_m.array()).all()))
      continue;
    const Eigen::Vector3d Xc = Rt * (X - T_world_left_.t);
    if (!(Xc.z() > 0)) continue;
    const Eigen::Vector2d uv = left_p_c_.project(Xc);
    const int px = static_cast<int>(std::floor(uv.x())), py = static_cast<int>(std::floor(uv.y()));
    // The nearest a-priori surface in the pixel's neighbourhood: a point beside an a-priori
    // outline is compared with the nearer of the two surfaces, so it is not taken as new.
    const int r = pair_.prior_window_px;
    float inv = 0.0f;
    for (int y = std::max(0, py - r); y <= std::min(h - 1, py + r); ++y)
      for (int x = std::max(0, px - r); x <= std::min(w - 1, px + r); ++x)
        inv = std::max(inv, prior_inv_depth_[static_cast<std::size_t>(y) * w + x]);
    if (inv <= 0.0f) {
      is_new_[i] = 1;  // nothing a priori along this ray
      continue;
    }
    const double z_prior = 1.0 / inv;
    const double margin =
        std::max(pair_.prior_margin_m, pair_.prior_margin_px * z_prior * z_prior / fB);
    is_new_[i] = Xc.z() < z_prior - margin;
  }
  // Pieces: vertices joined by triangles whose corners are all new.
  const std::size_t nv = dm.positions_m.size();
  parent_.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) parent_[i] = static_cast<uint32_t>(i);
  auto root = [this](uint32_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  };
  for (const auto& tri : dm.triangles) {
    if (!is_new_[tri[0]] || !is_new_[tri[1]] || !is_new_[tri[2]]) continue;
    const uint32_t a = root(tri[0]);
    parent_[root(tri[1])] = a;
    parent_[root(tri[2])] = a;
  }
  piece_size_.assign(nv, 0);
  for (std::size_t i = 0; i < nv; ++i)
    if (is_new_[i]) ++piece_size_[root(static_cast<uint32_t>(i))];
  const uint32_t min_piece = static_cast<uint32_t>(std::max(0, pair_.min_piece_vertices));

  remap_.assign(dm.positions_m.size(), -1);
  float s_lo = 1.0f, s_hi = 0.0f, t_lo = 1.0f, t_hi = 0.0f;
  for (const auto& tri : dm.triangles) {
    if (!is_new_[tri[0]] || !is_new_[tri[1]] || !is_new_[tri[2]]) continue;
    if (piece_size_[root(tri[0])] < min_piece) continue;
    if (mesh_.positions_m.size() + 3 > max_vertices_) break;  // never: the grid bounds it
    std::array<uint32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      int32_t& r = remap_[tri[k]];
      if (r < 0) {
        r = static_cast<int32_t>(mesh_.positions_m.size());
        mesh_.positions_m.push_back(dm.positions_m[tri[k]]);
        const Eigen::Vector2f& st = dm.texcoords[tri[k]];
        mesh_.uvs.push_back(st);
        s_lo = std::min(s_lo, st.x());
        s_hi = std::max(s_hi, st.x());
        t_lo = std::min(t_lo, st.y());
        t_hi = std::max(t_hi, st.y());
      }
      t[k] = static_cast<uint32_t>(r);
    }
    mesh_.triangles.push_back(t);
  }
  stats_.vertices_kept = mesh_.positions_m.size();
  stats_.triangles_kept = mesh_.triangles.size();
  if (mesh_.triangles.empty()) {
    mesh_.texture = render::ImageRgba8{};  // empty: both compositors skip the mesh
    return;
  }
  // The texture: the left frame cropped to the kept vertices (plus the bilinear border), so the
  // snapshot copies and the GPU uploads only what is drawn.
  const int W = left.width, H = left.height;
  const int x0 = std::clamp(static_cast<int>(std::floor(s_lo * W)) - 2, 0, W - 1);
  const int x1 = std::clamp(static_cast<int>(std::ceil(s_hi * W)) + 2, x0 + 1, W);
  const int y0 = std::clamp(static_cast<int>(std::floor(t_lo * H)) - 2, 0, H - 1);
  const int y1 = std::clamp(static_cast<int>(std::ceil(t_hi * H)) + 2, y0 + 1, H);
  const int cw = x1 - x0, ch = y1 - y0;
  if (mesh_.texture.width != cw || mesh_.texture.height != ch) mesh_.texture.allocate(cw, ch);
  for (int y = 0; y < ch; ++y)
    std::memcpy(mesh_.texture.row(y),
                left.data.data() + static_cast<std::ptrdiff_t>(y + y0) * left.stride_bytes + 4 * x0,
                static_cast<std::size_t>(cw) * 4);
  for (Eigen::Vector2f& st : mesh_.uvs)
    st = {(st.x() * static_cast<float>(W) - static_cast<float>(x0)) / static_cast<float>(cw),
          (st.y() * static_cast<float>(H) - static_cast<float>(y0)) / static_cast<float>(ch)};
}

}  // namespace hd::station
