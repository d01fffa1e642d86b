// The node-to-face contact kernel of sheet–sheet and self contact (docs/contact.md): the gap of
// a node x from the plane of a triangle (a, b, c), its gradient in the 12 coordinates and its
// Hessian (both in closed form, fixed size: allocation-free), the penalty force and stiffness
// of the pair, and its Coulomb friction (forward differentiation of fixed size).
#pragma once

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include <cmath>

#include "contact_law.hpp"
#include "velum/math/types.hpp"

namespace velum::contact {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// The gradient of g = (x − a)·n, n = (b − a)×(c − a)/|…|, in X = (x, a, b, c): with
/// q = (I − n nᵀ)(x − a)/|m|: ∂g/∂x = n, ∂g/∂c = q × u, ∂g/∂b = −q × v, ∂g/∂a = the rest
/// (the gap does not change under a translation).
template <class T>
Eigen::Matrix<T, 12, 1> plane_gap_gradient(const Eigen::Matrix<T, 12, 1>& X, T* gap = nullptr) {
  using V = Eigen::Matrix<T, 3, 1>;
  using std::sqrt;
  const V x = X.template segment<3>(0), a = X.template segment<3>(3), b = X.template segment<3>(6),
          c = X.template segment<3>(9);
  const V u = b - a, v = c - a, m = u.cross(v);
  const T M = sqrt(m.squaredNorm());
  const V n = m / M, r = x - a;
  const T g = r.dot(n);
  const V q = (r - g * n) / M;
  Eigen::Matrix<T, 12, 1> G;
  G.template segment<3>(0) = n;
  G.template segment<3>(9) = q.cross(u);
  G.template segment<3>(6) = -q.cross(v);
  G.template segment<3>(3) = -n - q.cross(u) + q.cross(v);
  if (gap) *gap = g;
  return G;
}

/// D += s ∇∇g at X (g: the gap there), ∇∇g in closed form (docs/contact.md, "Force and tangent"): g
/// depends on r = x − a, u = b − a, v = c − a only, and with M = |m|, P = I − n nᵀ, q = P r / M, S
/// = n qᵀ + q nᵀ + (g / M) P and [w]× the cross-product matrix,
///   ∂²g/∂r∂u = −P [v]× / M,  ∂²g/∂r∂v = P [u]× / M,  ∂²g/∂r² = 0,
///   ∂²g/∂u² = [v]× S [v]× / M,  ∂²g/∂v² = [u]× S [u]× / M,  ∂²g/∂u∂v = −[v]× S [u]× / M − [q]×
/// (from dn = P dm / M, dq = (P dr − S dm) / M, dm = −[v]× du + [u]× dv); a's rows and columns
/// are minus the sums of the others' (a translation leaves g). A few 3 x 3 products instead of
/// the forward differentiation of the 12-vector gradient that it replaces (the same to
/// round-off: tests/unit/load/sheet_contact_test.cpp).
inline void add_plane_gap_hessian(const Vec12& X, double g, double s, Mat12& D) {
  const Vec3 x = X.segment<3>(0), a = X.segment<3>(3), b = X.segment<3>(6), c = X.segment<3>(9);
  const Vec3 u = b - a, v = c - a, m = u.cross(v);
  const double M = m.norm();
  const Vec3 n = m / M;
  const Vec3 q = (x - a - g * n) / M;
  // s P / M and s S / M, so that every block below is s times its own (no division there).
  const double w = s / M;
  const Mat3 P = w * (Mat3::Identity() - n * n.transpose());
  const Mat3 S = w * (n * q.transpose() + q * n.transpose()) + (g / M) * P;
  const Mat3 U = cross_matrix(u), V = cross_matrix(v);
  const Mat3 SU = S * U, SV = S * V;
  // The blocks in (r, u, v), which are x's, b's and c's.
  Mat3 B[3][3];
  B[0][0].setZero();
  B[0][1] = -(P * V);
  B[0][2] = P * U;
  B[1][1] = V * SV;
  B[2][2] = U * SU;
  B[1][2] = -(V * SU) - s * cross_matrix(q);
  B[1][0] = B[0][1].transpose();
  B[2][0] = B[0][2].transpose();
  B[2][1] = B[1][2].transpose();
  constexpr int at[3] = {0, 6, 9};  // where r's, u's and v's coordinates are in X
  Mat3 to_a = Mat3::Zero();         // ∂²g/∂a²: the sum of every block
  for (int j = 0; j < 3; ++j) {
    const Mat3 col = B[0][j] + B[1][j] + B[2][j];  // minus ∂²g/∂a ∂(r, u, v)_j
    for (int i = 0; i < 3; ++i) D.block<3, 3>(at[i], at[j]) += B[i][j];
    D.block<3, 3>(3, at[j]) -= col;
    D.block<3, 3>(at[j], 3) -= col.transpose();
    to_a += col;
  }
  D.block<3, 3>(3, 3) += to_a;
}

/// ∇∇g at X (g: the gap there): add_plane_gap_hessian with s = 1 into zeros.
inline void plane_gap_hessian(const Vec12& X, double g, Mat12& H) {
  H.setZero();
  add_plane_gap_hessian(X, g, 1.0, H);
}

/// g and ∇g at X (as plane_gap_gradient computes them), and ∇∇g when asked.
inline double plane_gap(const Vec12& X, Vec12& grad, Mat12* hessian) {
  double g = 0;
  grad = plane_gap_gradient<double>(X, &g);
  if (hessian) plane_gap_hessian(X, g, *hessian);
  return g;
}

/// The barycentric coordinates (of b and c) of x's projection on the plane of (a, b, c).
inline Vec2 plane_coordinates(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - a, r = x - a;
  const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), ru = r.dot(u), rv = r.dot(v);
  const double det = uu * vv - uv * uv;
  if (!(det > 0)) return Vec2(-1, -1);
  return Vec2((vv * ru - uv * rv) / det, (uu * rv - uv * ru) / det);
}

struct PairResult {
  double gap = 0;  ///< side · g − thickness (negative: penetrating)
  double p = 0;    ///< the normal force
  Vec12 f;         ///< the forces on x, a, b, c
  Mat12 D;         ///< ∂f/∂X (filled when asked)
};

/// The penalty on a gap function g(X) (its gradient and, when asked, Hessian): G = side·g − c,
/// p = max(0, −k G), f = p side ∇g, ∂f/∂X = −k ∇g ∇gᵀ + p side ∇∇g (symmetric: the energy
/// ½ k G²). Node to face (plane_gap) and edge to edge (edge_gap) alike.
/// The normal penalty's part shared by every pair kind: r.gap, r.p and r.f from the gap g and
/// its gradient; false (r.p = 0) when the pair does not press.
inline bool normal_penalty(double g, const Vec12& grad, double side, double thickness, double k,
                           PairResult& r) {
  r.gap = side * g - thickness;
  r.p = -k * r.gap;
  if (r.p <= 0) {
    r.p = 0;
    return false;
  }
  r.f = (r.p * side) * grad;
  return true;
}

template <class Gap>
bool penalty_pair_force(Gap&& gap, const Vec12& X, double side, double thickness, double k,
                        bool tangent, PairResult& r) {
  Vec12 grad;
  Mat12 H;
  const double g = gap(X, grad, tangent ? &H : nullptr);
  if (!normal_penalty(g, grad, side, thickness, k, r)) return false;
  if (tangent) r.D = -k * grad * grad.transpose() + (r.p * side) * H;
  return true;
}

/// The node-to-face pair (x pushed to its side, the face the other way): penalty_pair_force on
/// the plane gap, its Hessian computed only for a pair that presses. `face_held`: the face's
/// corners have no equations, so of ∂f/∂X only the node's block is assembled, which needs no
/// Hessian (g is linear in x: ∂²g/∂x² = 0): D is then that block, −k n nᵀ, and zeros.
inline bool pair_force(const Vec12& X, double side, double thickness, double k, bool tangent,
                       PairResult& r, bool face_held = false) {
  Vec12 grad;
  const double g = plane_gap(X, grad, nullptr);
  if (!normal_penalty(g, grad, side, thickness, k, r)) return false;
  if (!tangent) return true;
  if (face_held) {
    r.D.setZero();
    r.D.topLeftCorner<3, 3>() = -k * grad.head<3>() * grad.head<3>().transpose();
    return true;
  }
  r.D = -k * grad * grad.transpose();
  add_plane_gap_hessian(X, g, r.p * side, r.D);
  return true;
}

}  // namespace velum::contact

namespace velum::contact {

/// The Coulomb return of a pair's tangential penalty (node–face and edge pairs alike): with e
/// the tangential part of the anchors' separation and p > 0 the normal pressure, f_T = −k e in
/// stick (k |e| <= μ p), −μ p e/|e| in slip; f_T is added to r with weights Ns over the pair's
/// four points, its derivative too with `tangent`. `kept`: the part of e the anchors keep at
/// an accepted state (μ p / (k |e|) in slip, 1 in stick).
template <class AD, class V>
Status coulomb_return(const V& e, const AD& p, double k, double mu, const double (&Ns)[4],
                      bool tangent, PairResult& r, double& kept) {
  const double en = std::sqrt(e[0].value() * e[0].value() + e[1].value() * e[1].value() +
                              e[2].value() * e[2].value());
  V fT;
  Status status = Status::kStick;
  kept = 1;
  if (k * en <= mu * p.value()) {
    fT = -k * e;
  } else {
    status = Status::kSlip;
    const AD len = sqrt(e.squaredNorm());
    fT = -(mu * p / len) * e;
    kept = mu * p.value() / (k * en);
  }
  for (int q = 0; q < 4; ++q)
    for (int i = 0; i < 3; ++i) {
      const AD v = Ns[q] * fT[i];
      r.f[3 * q + i] += v.value();
      if (tangent) r.D.row(3 * q + i) += v.derivatives().transpose();
    }
  return status;
}

/// Coulomb friction of a node–face pair (docs/contact.md, "Sheets"), added to a pair_force
/// result r (its p > 0): the tangential penalty k on e, the part in the face's plane of the
/// node's position minus the anchor (the face's point at barycentric coordinates xi0 of b and
/// c), returned to the cone |f_T| <= μ p (slip); the node takes f_T, the face's corners
/// −N_a(xi0) f_T. ∂f_T/∂X by forward differentiation of the force (exact for a fixed anchor;
/// unsymmetric). `slip`: the vector the anchor moves by at an accepted slip (0 in stick).
inline Status pair_friction(const Vec12& X, double side, double thickness, double k, double mu,
                            const Vec2& xi0, bool tangent, PairResult& r, Vec3& slip) {
  using AD = Eigen::AutoDiffScalar<Vec12>;
  using V = Eigen::Matrix<AD, 3, 1>;
  Eigen::Matrix<AD, 12, 1> Y;
  for (int i = 0; i < 12; ++i) Y[i] = tangent ? AD(X[i], 12, i) : AD(X[i]);
  const V x = Y.segment<3>(0), a = Y.segment<3>(3), b = Y.segment<3>(6), c = Y.segment<3>(9);
  const V m = (b - a).cross(c - a);
  const V n = m / sqrt(m.squaredNorm());
  const AD p = -k * (side * (x - a).dot(n) - thickness);
  const double N0 = 1 - xi0[0] - xi0[1];
  const V w = x - (N0 * a + xi0[0] * b + xi0[1] * c);
  const V e = w - w.dot(n) * n;
  const double Ns[4] = {1, -N0, -xi0[0], -xi0[1]};
  double kept = 1;
  const Status status = coulomb_return(e, p, k, mu, Ns, tangent, r, kept);
  // The anchor follows by the part of e it does not keep (0 in stick).
  for (int i = 0; i < 3; ++i) slip[i] = (1 - kept) * e[i].value();
  return status;
}

}  // namespace velum::contact
