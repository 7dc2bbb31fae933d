#include "core/view_setup.h"

#include <cmath>

namespace hd::core {

bool ViewSetup::valid() const {
  return real.valid() && virt.valid() && T_world_real.valid() && T_world_virt.valid() &&
         std::isfinite(d_m) && d_m > 0.0 && std::isfinite(near_m) && near_m > 0.0 &&
         workspace.valid();
}

}  // namespace hd::core
