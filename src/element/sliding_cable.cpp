#include "velum/element/sliding_cable.hpp"

#include <cmath>

namespace velum::sliding_cable {

double length(const Chain& x) {
  double l = 0;
  for (Eigen::Index j = 0; j + 1 < x.cols(); ++j) l += (x.col(j + 1) - x.col(j)).norm();
  return l;
}

// With U = A L0 W(ε) and dε/dl = l / L0²: r = A S (l / L0) ∂l/∂x, where ∂l/∂x gathers each
// segment's unit vector e_j (+ at its end node, − at its start node).
void force_tangent(const Chain& x, double L0, double area, const CableLaw& law, VectorMap r,
                   MatrixMap* K) {
  const Eigen::Index k = x.cols();
  const double l = length(x);
  const double lam = l / L0;
  const double eps = strain(l, L0);
  const double S = law.stress(eps);
  const double T = area * S * lam;
  // r holds ∂l/∂x until the end: each segment's unit vector, + at its end, − at its start.
  r.setZero();
  for (Eigen::Index j = 0; j + 1 < k; ++j) {
    const Vec3 d = x.col(j + 1) - x.col(j);
    const Vec3 e = d / d.norm();
    r.segment<3>(3 * (j + 1)) += e;
    r.segment<3>(3 * j) -= e;
  }
  if (K) {
    MatrixMap& Km = *K;
    Km.noalias() = (area / L0 * (law.tangent(eps) * lam * lam + S)) * r * r.transpose();
    for (Eigen::Index j = 0; T != 0 && j + 1 < k; ++j) {
      const Vec3 d = x.col(j + 1) - x.col(j);
      const double lj = d.norm();
      const Vec3 e = d / lj;
      const Mat3 G = (T / lj) * (Mat3::Identity() - e * e.transpose());
      Km.block<3, 3>(3 * j, 3 * j) += G;
      Km.block<3, 3>(3 * (j + 1), 3 * (j + 1)) += G;
      Km.block<3, 3>(3 * j, 3 * (j + 1)) -= G;
      Km.block<3, 3>(3 * (j + 1), 3 * j) -= G;
    }
  }
  r *= T;
}

double strain_energy(const Chain& x, double L0, double area, const CableLaw& law) {
  return area * L0 * law.energy(strain(length(x), L0));
}

double true_force(const Chain& x, double L0, double area, const CableLaw& law) {
  const double l = length(x);
  return area * law.stress(strain(l, L0)) * l / L0;
}

namespace {

double total(std::span<const double> L0j) {
  double L0 = 0;
  for (double l : L0j) L0 += l;
  return L0;
}

}  // namespace

void stabilized_force_tangent(const Chain& x, std::span<const double> L0j, double area, double S0,
                              double E, VectorMap r, MatrixMap* K) {
  // The prestress: the one-force chain of a law with S0 and no stiffness.
  force_tangent(x, total(L0j), area, CableLaw{.E = 0, .compression = true, .S0 = S0}, r, K);
  for (Eigen::Index j = 0; j + 1 < x.cols(); ++j) {
    const Vec3 d = x.col(j + 1) - x.col(j);
    const double lj = d.norm(), L = L0j[static_cast<size_t>(j)];
    const Vec3 e = d / lj;
    const double lam = lj / L, eps = strain(lj, L);
    const double T = area * E * eps * lam;
    r.segment<3>(3 * (j + 1)) += T * e;
    r.segment<3>(3 * j) -= T * e;
    if (!K) continue;
    const Mat3 G = (area / L * E * (lam * lam + eps)) * e * e.transpose() +
                   (T / lj) * (Mat3::Identity() - e * e.transpose());
    MatrixMap& Km = *K;
    Km.block<3, 3>(3 * j, 3 * j) += G;
    Km.block<3, 3>(3 * (j + 1), 3 * (j + 1)) += G;
    Km.block<3, 3>(3 * j, 3 * (j + 1)) -= G;
    Km.block<3, 3>(3 * (j + 1), 3 * j) -= G;
  }
}

double stabilized_strain_energy(const Chain& x, std::span<const double> L0j, double area, double S0,
                                double E) {
  const double L0 = total(L0j);
  double U = area * L0 * S0 * strain(length(x), L0);
  for (Eigen::Index j = 0; j + 1 < x.cols(); ++j) {
    const double L = L0j[static_cast<size_t>(j)];
    const double eps = strain((x.col(j + 1) - x.col(j)).norm(), L);
    U += 0.5 * area * L * E * eps * eps;
  }
  return U;
}

double stabilized_mean_force(const Chain& x, std::span<const double> L0j, double area, double S0,
                             double E) {
  const double l = length(x);
  double sum = area * S0 * l / total(L0j) * l;
  for (Eigen::Index j = 0; j + 1 < x.cols(); ++j) {
    const double lj = (x.col(j + 1) - x.col(j)).norm(), L = L0j[static_cast<size_t>(j)];
    sum += area * E * strain(lj, L) * lj / L * lj;
  }
  return sum / l;
}

}  // namespace velum::sliding_cable
