// A force on each node of a set (load type `point`), times its time function.
#pragma once

#include <memory>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

struct PointLoad {
  std::vector<int> nodes;
  Vec3 force = Vec3::Zero();  ///< on each node of the set
  int function = -1;
};

std::unique_ptr<Load> make_load(PointLoad p);

}  // namespace velum
