// A pressure on membrane elements (load type `pressure`), times its time function: a follower
// pressure along g1 x g2 per current area, or, with `fixed_direction`, a load along a fixed
// unit vector per area projected normal to it (snow per plan area) or per current area.
#pragma once

#include <memory>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

struct PressureLoad {
  int block = -1;
  std::vector<int> elements;  ///< indices into the block
  double value = 0;
  int function = -1;
  bool fixed_direction = false;
  Vec3 direction = Vec3::Zero();  ///< unit
  bool projected = true;
};

/// A follower pressure, or a directed one when p.fixed_direction.
std::unique_ptr<Load> make_load(PressureLoad p);

}  // namespace velum
