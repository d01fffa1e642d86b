#include "velum/material/plane_stress.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

namespace velum {
namespace {

void require(bool ok, const std::string& name, const std::string& what) {
  if (!ok) throw MaterialError(fmt::format("material '{}': {}", name, what));
}

// Tensor Q^{abcd} (a..d in {0,1}) from engineering Voigt and back (docs/theory.md).
using Tensor2222 = double[2][2][2][2];
constexpr int kVoigt[2][2] = {{0, 2}, {2, 1}};

void check_definite(const std::string& name, const Mat3& Q, bool semi) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(Q);
  const double lmin = eig.eigenvalues()(0), lmax = eig.eigenvalues()(2);
  if (semi) {
    require(lmin >= -1e-12 * std::abs(lmax), name,
            fmt::format("stiffness matrix Q is not positive semi-definite (smallest eigenvalue "
                        "{:.6g})",
                        lmin));
  } else {
    require(lmin > 1e-12 * std::abs(lmax), name,
            fmt::format("stiffness matrix Q is not positive definite (smallest eigenvalue {:.6g}); "
                        "check nu12, G12, eta1, eta2",
                        lmin));
  }
}

}  // namespace

double firt_shear_modulus(double E1, double E2, double nu12) {
  const double nu21 = nu12 * E2 / E1;
  return std::sqrt(E1 * E2) / (2 * (1 + std::sqrt(nu12 * nu21)));
}

Mat3 compliance(const AnisotropicConstants& c) {
  const double nu21 = c.nu12 * c.E2 / c.E1;
  const double G = c.use_firt ? firt_shear_modulus(c.E1, c.E2, c.nu12) : c.G12;
  Mat3 S;
  S << 1 / c.E1, -nu21 / c.E2, c.eta1 / c.E1,   //
      -c.nu12 / c.E1, 1 / c.E2, c.eta2 / c.E2,  //
      c.eta1 / c.E1, c.eta2 / c.E2, 1 / G;
  return S;
}

PlaneStressLaw PlaneStressLaw::isotropic(const std::string& name, double E, double nu) {
  require(E > 0, name, fmt::format("Young's modulus E must be positive (got {})", E));
  require(nu > -1 && nu < 1, name,
          fmt::format("Poisson's ratio nu must lie in (-1, 1) for plane stress (got {})", nu));
  return anisotropic(name, {E, E, nu, E / (2 * (1 + nu)), false, 0, 0});
}

PlaneStressLaw PlaneStressLaw::orthotropic(const std::string& name, double E1, double E2,
                                           double nu12, double G12, bool use_firt) {
  return anisotropic(name, {E1, E2, nu12, G12, use_firt, 0, 0});
}

PlaneStressLaw PlaneStressLaw::anisotropic(const std::string& name, const AnisotropicConstants& c) {
  require(c.E1 > 0, name, fmt::format("E1 must be positive (got {})", c.E1));
  require(c.E2 > 0, name, fmt::format("E2 must be positive (got {})", c.E2));
  require(
      c.nu12 * c.nu12 < c.E1 / c.E2, name,
      fmt::format("nu12^2 = {:.6g} must be below E1/E2 = {:.6g}", c.nu12 * c.nu12, c.E1 / c.E2));
  require(c.nu12 >= 0 || !c.use_firt, name, "Firt's approximation needs nu12 >= 0");
  const double G = c.use_firt ? firt_shear_modulus(c.E1, c.E2, c.nu12) : c.G12;
  require(G > 0, name, fmt::format("shear modulus G12 must be positive (got {})", G));
  const double E1 = c.E1, E2 = c.E2, n12 = c.nu12, n21 = n12 * E2 / E1;
  const double e1 = c.eta1, e2 = c.eta2;
  const double delta =
      (1 - n12 * n21) - (G / E1) * (2 * n12 * e1 * e2 + e1 * e1 + (E1 / E2) * e2 * e2);
  require(delta > 0, name,
          fmt::format("the law is not admissible: Delta = {:.6g} <= 0 (Eq. 21); reduce eta1, eta2 "
                      "or nu12",
                      delta));
  Mat3 Q;
  Q(0, 0) = E1 * (1 - G * e2 * e2 / E2) / delta;
  Q(1, 1) = E2 * (1 - G * e1 * e1 / E1) / delta;
  Q(0, 1) = Q(1, 0) = (E2 * n12 + G * e1 * e2) / delta;
  Q(2, 2) = G * (1 - n12 * n21) / delta;
  Q(0, 2) = Q(2, 0) = -G * (e1 + n12 * e2) / delta;
  Q(1, 2) = Q(2, 1) = -G * (e2 + n21 * e1) / delta;
  check_definite(name, Q, false);
  return PlaneStressLaw(name, Q);
}

PlaneStressLaw PlaneStressLaw::fibers(const std::string& name,
                                      const std::vector<FiberFamily>& families) {
  require(!families.empty(), name, "a fibre material needs at least one fibre family");
  Tensor2222 q{};
  for (const FiberFamily& f : families) {
    require(f.E > 0, name, fmt::format("fibre modulus E must be positive (got {})", f.E));
    const double th = f.angle_deg * std::numbers::pi / 180;
    const double n[2] = {std::cos(th), std::sin(th)};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c)
          for (int d = 0; d < 2; ++d) q[a][b][c][d] += f.E * n[a] * n[b] * n[c] * n[d];
  }
  Mat3 Q;
  for (int a = 0; a < 2; ++a)
    for (int b = a; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = c; d < 2; ++d) Q(kVoigt[a][b], kVoigt[c][d]) = q[a][b][c][d];
  PlaneStressLaw law(name, Q);
  law.families_ = families;
  return law;
}

PlaneStressLaw PlaneStressLaw::matrix(const std::string& name, const Mat3& Q) {
  require((Q - Q.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * Q.cwiseAbs().maxCoeff(), name,
          "matrix Q must be symmetric");
  require(Q.cwiseAbs().maxCoeff() > 0, name, "matrix Q is zero");
  check_definite(name, Q, true);
  return PlaneStressLaw(name, Q);
}

Mat3 transform_stiffness(const Mat3& Q, const Mat2& T) {
  // Q^{abcd} has only the independent Voigt entries; contract index pairs one at a time:
  // P(ab, γδ) = Q^{abcd} T(c,γ) T(d,δ), then out(αβ, γδ) = T(a,α) T(b,β) P(ab, γδ).
  // Pair (a,b) runs over (0,0), (1,1), (0,1), (1,0); Voigt row of (0,1) and (1,0) is 2.
  constexpr int pa[4] = {0, 1, 0, 1}, pb[4] = {0, 1, 1, 0};
  constexpr int va[3] = {0, 1, 0}, vb[3] = {0, 1, 1};
  Eigen::Matrix<double, 4, 3> P;  // rows: pair (a,b); cols: Voigt (γδ)
  for (int r = 0; r < 4; ++r) {
    const int row = kVoigt[pa[r]][pb[r]];
    for (int k = 0; k < 3; ++k) {
      double s = 0;
      for (int c = 0; c < 4; ++c)
        s += Q(row, kVoigt[pa[c]][pb[c]]) * T(pa[c], va[k]) * T(pb[c], vb[k]);
      P(r, k) = s;
    }
  }
  Mat3 out;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      double s = 0;
      for (int r = 0; r < 4; ++r) s += T(pa[r], va[i]) * T(pb[r], vb[i]) * P(r, k);
      out(i, k) = s;
    }
  return out;
}

}  // namespace velum
