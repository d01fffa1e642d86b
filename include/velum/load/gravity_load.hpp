// Gravity on the whole model (load type `gravity`): the consistent mass (point masses
// included) times an acceleration, times its time function.
#pragma once

#include <memory>

#include "velum/load/load.hpp"

namespace velum {

struct GravityLoad {
  Vec3 acceleration = Vec3::Zero();
  int function = -1;
};

std::unique_ptr<Load> make_load(GravityLoad p);

}  // namespace velum
