#include "velum/element/stress_output.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace velum {

MembraneStress membrane_stress(const Eigen::Matrix<double, 3, 2>& g, const Vec3& S, const Vec3& Gm,
                               const Mat2& T) {
  MembraneStress out;
  const Mat2 gcov = g.transpose() * g;
  const double detG = Gm[0] * Gm[1] - Gm[2] * Gm[2];
  const double J = std::sqrt(gcov.determinant() / detG);
  Mat2 Sm;
  Sm << S[0], S[2], S[2], S[1];
  out.sigma = g * Sm * g.transpose() / J;  // F S Fᵀ = S^{αβ} g_α ⊗ g_β

  // Deformed material directions F m_a = g_α T(a, α).
  const Vec3 f1 = g * T.row(0).transpose(), f2 = g * T.row(1).transpose();
  const Vec3 n = g.col(0).cross(g.col(1)).normalized();
  const Vec3 a1 = f1.normalized(), a2 = n.cross(a1);
  Mat2 s2;
  s2 << a1.dot(out.sigma * a1), a1.dot(out.sigma * a2), a2.dot(out.sigma * a1),
      a2.dot(out.sigma * a2);
  out.sheet = Vec3(s2(0, 0), s2(1, 1), s2(0, 1));
  Eigen::SelfAdjointEigenSolver<Mat2> eig(s2);
  out.min = eig.eigenvalues()(0);
  out.max = eig.eigenvalues()(1);
  out.dir_min = (eig.eigenvectors()(0, 0) * a1 + eig.eigenvectors()(1, 0) * a2).normalized();
  out.dir_max = (eig.eigenvectors()(0, 1) * a1 + eig.eigenvectors()(1, 1) * a2).normalized();
  const double c = std::clamp(f1.dot(f2) / (f1.norm() * f2.norm()), -1.0, 1.0);
  out.fiber_angle_change = std::acos(c) - std::numbers::pi / 2;  // m1 ⟂ m2 in the reference
  out.axis1 = a1;
  out.axis2 = a2;
  out.normal = n;
  out.fiber2 = f2.normalized();

  // E_ab = T(a,α) E_αβ T(b,β) with E_αβ = ½ (g_α·g_β − G_αβ); m1, m2 are orthonormal in the
  // reference, so C = I + 2 E in those axes and its eigenvalues are the squared stretches.
  Mat2 Gcov;
  Gcov << Gm[0], Gm[2], Gm[2], Gm[1];
  const Mat2 E = T * (0.5 * (gcov - Gcov)) * T.transpose();
  out.strain = Vec3(E(0, 0), E(1, 1), 0.5 * (E(0, 1) + E(1, 0)));
  Eigen::SelfAdjointEigenSolver<Mat2> stretch(Mat2::Identity() + 2 * E, Eigen::EigenvaluesOnly);
  out.stretch_min = std::sqrt(std::max(stretch.eigenvalues()(0), 0.0));
  out.stretch_max = std::sqrt(std::max(stretch.eigenvalues()(1), 0.0));
  return out;
}

}  // namespace velum
