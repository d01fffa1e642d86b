// Small fixed-size linear-algebra types shared by every layer (Eigen aliases) and the
// VELUM_ASSERT invariant check (active in debug builds only).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cassert>

namespace velum {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// Skew-symmetric matrix [a]x with [a]x b = a x b.
inline Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

}  // namespace velum

#ifdef VELUM_DEBUG
#define VELUM_ASSERT(cond) assert(cond)
#else
#define VELUM_ASSERT(cond) ((void)0)
#endif
