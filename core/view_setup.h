#pragma once
// One real camera against the operator's virtual camera: every input of the per-frame geometry.

#include "core/pinhole.h"
#include "core/pose.h"
#include "core/workspace_box.h"

namespace hd::core {

/// p_c, P_c (real camera), p_o, P_o (virtual camera), the projection plane z_c = d in the real
/// camera frame, the near distance used for "in front of a camera", and the workspace box W is cut
/// from (DESIGN.md "Reading the paper with care" 1-4).
struct ViewSetup {
  Pinhole real;
  Pose T_world_real;  ///< P_c
  Pinhole virt;
  Pose T_world_virt;  ///< P_o
  double d_m = 1.0;   ///< projection plane z_c = d (real camera frame), > 0
  double near_m = 0.01;
  WorkspaceBox workspace;

  /// Both pinholes and poses valid, d and near finite and positive, the box valid. Every
  /// function of core treats an invalid setup as "no usable video" (m = +inf, no region).
  bool valid() const;
};

}  // namespace hd::core
