// The edge-to-edge kernel of self and sheet contact (docs/contact.md, "Sheets"): the gap of two
// straight edges (a, b) and (c, d) across their common normal, g = (a − c)·n with
// n = (b − a)×(d − c)/|…| (the distance of the closest points while they lie inside both
// edges), its gradient in the 12 coordinates and its Hessian by nested forward
// differentiation of fixed size (allocation-free), and the penalty pair of face_contact.hpp.
#pragma once

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include <cmath>

#include "face_contact.hpp"

namespace velum::contact {

template <class T>
T edge_gap(const Eigen::Matrix<T, 12, 1>& X) {
  using V = Eigen::Matrix<T, 3, 1>;
  using std::sqrt;
  const V a = X.template segment<3>(0), b = X.template segment<3>(3), c = X.template segment<3>(6),
          d = X.template segment<3>(9);
  const V m = (b - a).cross(d - c);
  return (a - c).dot(m) / sqrt(m.squaredNorm());
}

/// The closest points' parameters s on (a, b) and t on (c, d); false for parallel edges.
inline bool edge_parameters(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& s,
                            double& t) {
  const Vec3 u = b - a, v = d - c, w = a - c;
  const double A = u.dot(u), B = u.dot(v), C = v.dot(v), D = u.dot(w), E = v.dot(w);
  const double det = A * C - B * B;
  if (!(det > 1e-12 * A * C)) return false;
  s = (B * E - C * D) / det;
  t = (A * E - B * D) / det;
  return true;
}

/// g, ∇g and (when asked) ∇∇g at X.
inline double edge_gap(const Vec12& X, Vec12& grad, Mat12* hessian) {
  using AD = Eigen::AutoDiffScalar<Vec12>;
  if (!hessian) {
    Eigen::Matrix<AD, 12, 1> Y;
    for (int i = 0; i < 12; ++i) Y[i] = AD(X[i], 12, i);
    const AD g = edge_gap<AD>(Y);
    grad = g.derivatives();
    return g.value();
  }
  using AD2 = Eigen::AutoDiffScalar<Eigen::Matrix<AD, 12, 1>>;
  Eigen::Matrix<AD2, 12, 1> Y;
  for (int i = 0; i < 12; ++i) {
    Y[i].value() = AD(X[i], 12, i);
    Y[i].derivatives().setZero();
    Y[i].derivatives()[i] = AD(1.0, Vec12::Zero());
  }
  const AD2 g = edge_gap<AD2>(Y);
  for (int i = 0; i < 12; ++i) {
    grad[i] = g.derivatives()[i].value();
    hessian->row(i) = g.derivatives()[i].derivatives().transpose();
  }
  return g.value().value();
}

/// The penalty pair of two edges (face_contact.hpp's penalty on the edges' gap).
inline bool edge_pair_force(const Vec12& X, double side, double thickness, double k, bool tangent,
                            PairResult& r) {
  return penalty_pair_force([](const Vec12& Y, Vec12& g, Mat12* H) { return edge_gap(Y, g, H); }, X,
                            side, thickness, k, tangent, r);
}

}  // namespace velum::contact
