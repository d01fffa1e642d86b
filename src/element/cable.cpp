#include "velum/element/cable.hpp"

#include <cmath>
#include <limits>

namespace velum {

template <class Shape>
double Cable<Shape>::setup(const Nodes& X, double E, double area, Points& pts,
                           shape::Integration integration) {
  const auto rule = shape::rule_of<Shape>(integration);
  double min_len = std::numeric_limits<double>::infinity();
  for (int q = 0; q < kQ; ++q) {
    auto& p = pts[q];
    Shape::eval(rule.xi[q][0], p.N, p.dN);
    const Vec3 Xp = X * p.dN;
    p.L0sq = Xp.squaredNorm();
    p.w = rule.w[q];
    const double L0 = std::sqrt(p.L0sq);
    min_len = std::min(min_len, L0);
    p.EAw = L0 > 0 ? E * area * p.w / L0 : 0.0;  // ∫ ... ds = Σ w L0, and ∂ε/∂x carries 1/L0²
  }
  return min_len;
}

// Per point, with ε = ½(|x'|²/L0² − 1), s = N/(EA) and k = (dN/dε)/(EA), ds = L0 dξ and
// ∂ε/∂x_N = dN_N x'/L0²:  r_N = EAw s dN_N x',  K_MN = EAw dN_M dN_N (s I + k x' x'ᵀ/L0²).
template <class Shape>
void Cable<Shape>::force(const Points& pts, const CableLaw& law, const Nodes& x, Vector& r) {
  Eigen::Matrix<double, 3, kN> rn = Eigen::Matrix<double, 3, kN>::Zero();
  for (const auto& p : pts) {
    const Vec3 xp = x * p.dN;
    const double eps = 0.5 * (xp.squaredNorm() / p.L0sq - 1);
    const double s = law.stress(eps) / law.E;  // force ratio N/(EA)
    rn.noalias() += (p.EAw * s) * xp * p.dN.transpose();
  }
  r = Eigen::Map<const Vector>(rn.data());
}

template <class Shape>
void Cable<Shape>::force_tangent(const Points& pts, const CableLaw& law, const Nodes& x, Vector& r,
                                 Matrix& K) {
  Eigen::Matrix<double, 3, kN> rn = Eigen::Matrix<double, 3, kN>::Zero();
  K.setZero();
  for (const auto& p : pts) {
    const Vec3 xp = x * p.dN;
    const double eps = 0.5 * (xp.squaredNorm() / p.L0sq - 1);
    const double s = law.stress(eps) / law.E;
    const double k = law.tangent(eps) / law.E;
    const double c = p.EAw;
    rn.noalias() += (c * s) * xp * p.dN.transpose();
    const Mat3 xx = (c * k / p.L0sq) * xp * xp.transpose();
    for (int m = 0; m < kN; ++m)
      for (int n = 0; n < kN; ++n) {
        auto blk = K.template block<3, 3>(3 * m, 3 * n);
        blk += (p.dN[m] * p.dN[n]) * xx;
        blk.diagonal().array() += c * s * p.dN[m] * p.dN[n];
      }
  }
  r = Eigen::Map<const Vector>(rn.data());
}

template <class Shape>
bool Cable<Shape>::keeps_orientation(const Points& pts, const Nodes& from, const Nodes& to) {
  for (const auto& p : pts)
    if (!((from * p.dN).dot(to * p.dN) > 0)) return false;
  return true;
}

template <class Shape>
double Cable<Shape>::strain_energy(const Points& pts, const CableLaw& law, const Nodes& x) {
  double U = 0;
  for (const auto& p : pts) {
    const Vec3 xp = x * p.dN;
    const double eps = 0.5 * (xp.squaredNorm() / p.L0sq - 1);
    U += p.EAw * p.L0sq * law.energy(eps) / law.E;
  }
  return U;
}

template <class Shape>
typename Cable<Shape>::NodeMatrix Cable<Shape>::mass(const Points& pts) {
  NodeMatrix M = NodeMatrix::Zero();
  for (const auto& p : pts) M.noalias() += (p.w * std::sqrt(p.L0sq)) * p.N * p.N.transpose();
  return M;
}

template <class Shape>
typename Cable<Shape>::NodeMatrix Cable<Shape>::tension_stiffness(const Points& pts) {
  NodeMatrix K = NodeMatrix::Zero();
  for (const auto& p : pts) K.noalias() += (p.w / std::sqrt(p.L0sq)) * p.dN * p.dN.transpose();
  return K;
}

template <class Shape>
double Cable<Shape>::length(const Points& pts) {
  double L = 0;
  for (const auto& p : pts) L += p.w * std::sqrt(p.L0sq);
  return L;
}

template <class Shape>
double Cable<Shape>::true_force(const Points& pts, const CableLaw& law, const Nodes& x) {
  double F = 0, W = 0;
  for (const auto& p : pts) {
    const Vec3 xp = x * p.dN;
    const double lam2 = xp.squaredNorm() / p.L0sq;
    const double eps = 0.5 * (lam2 - 1);
    // EAw·L0/w = E A: the true force is E A ε λ (2nd PK force times stretch).
    const double EA = p.EAw * std::sqrt(p.L0sq) / p.w;
    F += p.w * EA * law.stress(eps) / law.E * std::sqrt(lam2);
    W += p.w;
  }
  return F / W;
}

template struct Cable<shape::Line2>;
template struct Cable<shape::Line3>;

}  // namespace velum
