// The element benchmarks' deformation: a stretch with shear, then a finite rotation, so that
// the kernels see neither an identity nor an axis-aligned state.
#pragma once

#include <Eigen/Geometry>

#include "velum/math/types.hpp"

namespace velum::bench {

inline Mat3 rotated_stretch() {
  Mat3 F;
  F << 1.08, 0.05, 0.0, -0.03, 0.97, 0.0, 0.02, 0.04, 1.0;
  return Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix() * F;
}

}  // namespace velum::bench
