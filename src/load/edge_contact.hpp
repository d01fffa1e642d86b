// The edge-to-edge kernel of self and sheet contact (docs/contact.md, "Sheets"): the gap of two
// straight edges (a, b) and (c, d) across their common normal, g = (a − c)·n with
// n = (b − a)×(d − c)/|…| (the distance of the closest points while they lie inside both
// edges), its gradient in the 12 coordinates and its Hessian by nested forward
// differentiation of fixed size (allocation-free), the penalty pair of face_contact.hpp and
// its Coulomb friction.
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

/// Coulomb friction of an edge pair (docs/contact.md, "Sheets"), added to an edge_pair_force
/// result r (its p > 0): the tangential penalty k on e, the part across the common normal n of
/// w = P(s0) − Q(t0), the edges' material points (s0 on (a, b), t0 on (c, d)) that touched at
/// the anchor, returned to the cone |f_T| <= μ p (slip); (a, b) take (1 − s0, s0) f_T, (c, d)
/// −(1 − t0, t0) f_T (no net force). ∂f/∂X by forward differentiation of the force (exact for
/// fixed anchors; unsymmetric). `keep`: the part of e the anchors keep at an accepted state
/// (μ p / (k |e|) in slip, 1 in stick): with the closest points (s, t) now, the anchors move
/// to s + keep (s0 − s), t + keep (t0 − t) (e is (s0 − s)(b − a) − (t0 − t)(d − c) exactly).
inline Status edge_friction(const Vec12& X, double side, double thickness, double k, double mu,
                            const Vec2& st0, bool tangent, PairResult& r, double& keep) {
  using AD = Eigen::AutoDiffScalar<Vec12>;
  using V = Eigen::Matrix<AD, 3, 1>;
  Eigen::Matrix<AD, 12, 1> Y;
  for (int i = 0; i < 12; ++i) Y[i] = tangent ? AD(X[i], 12, i) : AD(X[i]);
  const V a = Y.segment<3>(0), b = Y.segment<3>(3), c = Y.segment<3>(6), d = Y.segment<3>(9);
  const V m = (b - a).cross(d - c);
  const V n = m / sqrt(m.squaredNorm());
  const AD p = -k * (side * (a - c).dot(n) - thickness);
  const double s0 = st0[0], t0 = st0[1];
  const V w = ((1 - s0) * a + s0 * b) - ((1 - t0) * c + t0 * d);
  const V e = w - w.dot(n) * n;
  const double Ns[4] = {1 - s0, s0, -(1 - t0), -t0};
  return coulomb_return(e, p, k, mu, Ns, tangent, r, keep);
}

}  // namespace velum::contact
