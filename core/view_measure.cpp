#include "core/view_measure.h"

#include <cmath>
#include <limits>

#include "core/camera_pair.h"
#include "core/coverage.h"
#include "core/observation_space.h"
#include "core/update_region.h"

namespace hd::core {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

double max_error_at_vertices(const ViewSetup& s) {
  if (!s.valid()) return kInf;
  const ConvexPolyhedron W = observation_space(s);
  const CameraPair pair(s);
  double e_max = 0.0;
  W.for_each_vertex_once_per_box_face([&](const Eigen::Vector3d& X) {
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
  vm.coverage = coverage(s);
  vm.m = (vm.coverage > 0.0 && std::isfinite(vm.e_max_px)) ? vm.e_max_px / vm.coverage : kInf;
  if (const auto r = update_region(s)) {
    vm.has_region = true;
    vm.region = *r;
  }
  return vm;
}

}  // namespace hd::core
