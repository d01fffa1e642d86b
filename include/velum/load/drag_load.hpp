// Aerodynamic drag on a node (a payload's point mass, `masses: drag`): f = −½ ρ C_D A |v| v
// on the node's velocity.
#pragma once

#include <memory>

#include "velum/load/load.hpp"

namespace velum {

struct DragLoad {
  int node = -1;
  double rho = 0, cd_area = 0;  ///< air density and C_D A; off when either is zero
};

std::unique_ptr<Load> make_load(DragLoad p);

}  // namespace velum
