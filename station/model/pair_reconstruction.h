#pragma once
// One stereo pair of the model updater: the pair's depth mesh, cut to what the a-priori model does
// not already hold, as a textured mesh the station draws beside the a-priori meshes.

#include <cstdint>
#include <string>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "core/workspace_box.h"
#include "drivers/frame.h"
#include "recon/stereo_reconstructor.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::station {

/// Which two of the updater's cameras (ModelCamera indices) form a pair, and how they are matched.
struct ModelStereoPair {
  std::size_t left = 0;  ///< the camera whose pixels (and frame, as texture) the mesh uses
  std::size_t right = 1;
  recon::ReconstructionConfig reconstruction{};
  /// Reconstructed at every n-th model update (1: at the model's rate); between them the last
  /// mesh stays, and its capture time keeps counting in the model's age.
  int every_updates = 1;
  /// A reconstructed vertex is new geometry (kept) only when it lies in front of the nearest
  /// a-priori surface along its left-camera ray by more than
  /// max(prior_margin_m, prior_margin_px * z^2 / (f B)) (z: that surface's depth; z^2 / (f B)
  /// is the depth of one pixel of disparity there: 4.5 cm at 1.5 m, 9.6 cm at 2.2 m in the
  /// default scene). Points on the a-priori geometry are dropped: it stays as it is, sharp and
  /// textured by every camera. 1.5 px covers the matcher's tail of errors (docs/reconstruction.md).
  double prior_margin_px = 1.5;
  double prior_margin_m = 0.01;
  /// With use_bounds, vertices outside `bounds` are dropped: the workspace (what the robot can
  /// reach) is what the model needs, and beyond it lie surfaces no a-priori model describes.
  core::WorkspaceBox bounds{};
  bool use_bounds = false;
  /// The a-priori depth a vertex is compared with is the nearest one within this many pixels of
  /// its own: the matcher smears an a-priori surface a few pixels past its outline (the guided
  /// upsampling and the mesh's grid), where nothing may be behind it a priori.
  int prior_window_px = 3;
  /// Pieces of new surface (connected triangles) with fewer vertices than this are dropped:
  /// mismatches in textureless patches and at outlines come as small islands, objects as
  /// larger ones (the default scene's 8 cm block: ~130 vertices at a 2 px grid).
  int min_piece_vertices = 24;
  /// What a surface seen from one side hides behind it, for the texture extractor only: the
  /// reconstructed mesh is also put this far behind itself (and half as far) along the left
  /// camera's rays as occluders that are never drawn, so another camera does not paint an
  /// object's colours onto the table behind it (the object's back is not reconstructed).
  double occluder_depth_m = 0.1;
  std::string name;  ///< "cam0+cam0r", for messages
};

/// What the newest reconstruction did.
struct PairReconstructionStats {
  recon::PairStatus status = recon::PairStatus::kOk;
  std::string message;
  double reconstruct_ms = 0.0;        ///< recon::StereoReconstructor (rectify, match, filter, mesh)
  double cut_ms = 0.0;                ///< the a-priori comparison and the texture crop
  std::size_t vertices_measured = 0;  ///< of the depth mesh
  std::size_t vertices_kept = 0;      ///< not on the a-priori geometry
  std::size_t triangles_kept = 0;
};

/// The a-priori depth the left camera sees is rasterised once (the a-priori model is static).
/// update() reconstructs a pair of frames and rebuilds mesh(): its vertices are the depth mesh's
/// new ones in world metres, its texture the left frame cropped to them (texture and geometry
/// of the same instant). A refused pair (missing, unsynchronised, not newer) keeps the previous
/// mesh and capture time; a pair that matched nothing empties the mesh (it was measured).
/// Runs on the updater's thread; allocates there.
class PairReconstruction {
 public:
  /// `prior`: the a-priori model (static geometry). Throws recon::RigError (naming the pair) when
  /// the cameras cannot form a pair, std::invalid_argument for a bad config.
  PairReconstruction(const ModelStereoPair& pair, const core::Pinhole& left_p_c,
                     const core::Pose& T_world_left, const core::Pinhole& right_p_c,
                     const core::Pose& T_world_right, const render::SyntheticScene& prior);

  /// Returns whether mesh() changed (ok, or nothing matched).
  bool update(const drivers::Frame& left, const drivers::Frame& right);

  const ModelStereoPair& pair() const { return pair_; }
  /// The most vertices mesh() can have: the depth mesh's grid over the left image. The updater's
  /// initial model holds a placeholder of this many (not drawn), so the station's rasteriser
  /// reaches its final size before the first reconstruction arrives and never grows after.
  std::size_t max_vertices() const { return max_vertices_; }
  const render::TexturedMesh& mesh() const { return mesh_; }
  /// The older capture time of the frames mesh() was measured from; 0 before the first.
  int64_t capture_ns() const { return capture_ns_; }
  const PairReconstructionStats& last_stats() const { return stats_; }
  const recon::StereoReconstructor& reconstructor() const { return recon_; }

 private:
  void cut(const drivers::Frame& left);

  ModelStereoPair pair_;
  core::Pinhole left_p_c_;
  core::Pose T_world_left_;
  recon::StereoReconstructor recon_;
  std::vector<float> prior_inv_depth_;  ///< left camera pixels, 1/z of the a-priori model (0: none)
  recon::Reconstruction out_;
  render::TexturedMesh mesh_;
  std::vector<int32_t> remap_;
  std::vector<uint8_t> is_new_;
  std::vector<uint32_t> parent_;  ///< union-find over the depth mesh's vertices
  std::vector<uint32_t> piece_size_;
  int64_t capture_ns_ = 0;
  std::size_t max_vertices_ = 0;
  PairReconstructionStats stats_;
};

}  // namespace hd::station
