#include "core/view_measure.h"

#include <cmath>
#include <limits>

#include "core/camera_pair.h"
#include "core/coverage.h"
#include "core/observation_space.h"
#include "core/update_region.h"
#include "core/video_quad.h"

namespace hd::core {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

double max_error_at_vertices(const ViewSetup& s) {
  if (!s.valid()) return kInf;
  const CameraPair pair(s);
  double e_max = 0.0;
  // W's vertices straight from the half-spaces: building W's face polygons (observation_space)
  // costs several times more and the maximum needs only the vertices.
  const auto cuts = observation_space_cuts(s);
  ConvexPolyhedron::for_each_vertex_of_box_cut(
      s.workspace, cuts.data(), static_cast<int>(cuts.size()), geometry_tolerance_m(s),
      [&](const Eigen::Vector3d& X) {
        const double e = pair.error_px(pair.real_from_world(X));
        // NaN cannot arise from a valid setup; if it ever did, "unusable" is the safe reading.
        e_max = std::isnan(e) ? kInf : std::max(e_max, e);
      });
  return e_max;
}

ViewMeasure measure_view(const ViewSetup& s) {
  if (!s.valid()) return {kInf, 0.0, kInf, false, {}};
  ViewMeasure vm{};
  vm.e_max_px = max_error_at_vertices(s);
  // One video quad serves both coverage and the region.
  const CameraPair pair(s);
  VideoQuad quad = video_quad_in_virtual(pair);
  clip_to_virtual_frustum(quad, s);
  vm.coverage = coverage_of_clipped_quad(quad, s);
  vm.m = (vm.coverage > 0.0 && std::isfinite(vm.e_max_px)) ? vm.e_max_px / vm.coverage : kInf;
  if (const auto r = region_of_clipped_quad(quad, pair)) {
    vm.has_region = true;
    vm.region = *r;
  }
  return vm;
}

}  // namespace hd::core
