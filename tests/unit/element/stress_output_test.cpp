// Output quantities of a membrane point (THEORY §9): true stress and principal directions under
// a uniaxial stress state, and the change of the angle between the material directions under
// simple shear.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "velum/element/membrane.hpp"
#include "velum/element/stress_output.hpp"

namespace velum {
namespace {

using M = Membrane<shape::Quad4>;

// A unit square sheet in the plane rotated by R0; nodes moved by x = R F X (F in the sheet's
// local coordinates, R a rigid rotation of the deformed sheet).
struct Sheet {
  M::Nodes X, x;
  M::Points pts;
};

Sheet make_sheet(const PlaneStressLaw& law, double axes_deg, const Mat3& R0, const Mat3& F,
                 const Mat3& R) {
  Sheet s;
  const auto nodes = shape::Quad4::nodes();
  for (int n = 0; n < 4; ++n) {
    const Vec3 p(0.5 * (nodes[n][0] + 1), 0.5 * (nodes[n][1] + 1), 0);
    s.X.col(n) = R0 * p;
    s.x.col(n) = R * R0 * F * p;
  }
  M::setup(s.X, law.Q(), test::axes_at(axes_deg, R0), 0.1, s.pts);
  return s;
}

MembraneStress output(const Sheet& s, int q) {
  Vec3 e, S;
  Eigen::Matrix<double, 3, 2> g;
  M::strain_stress(s.pts, q, s.x, e, S, g);
  return membrane_stress(g, S, s.pts[q].G, s.pts[q].T);
}

TEST(StressOutput, UniaxialStressGivesTrueStressAndDirections) {
  const double E = 1000, nu = 0.3, lam1 = 1.2;
  const auto law = PlaneStressLaw::isotropic("iso", E, nu);
  // Uniaxial 2nd PK stress along local x: E22 = −ν E11 (S22 = 0), so λ2² = 1 − ν (λ1² − 1).
  const double E11 = 0.5 * (lam1 * lam1 - 1), lam2 = std::sqrt(1 - nu * (lam1 * lam1 - 1));
  const double S11 = E * E11;
  // True stress: σ = F S Fᵀ / J with J = λ1 λ2 (thickness held).
  const double sigma = lam1 * lam1 * S11 / (lam1 * lam2);
  test::Random rnd(17);
  const Mat3 R0 = rnd.rotation(0.8), R = rnd.rotation(2.4);
  const Mat3 F = Vec3(lam1, lam2, 1).asDiagonal();
  for (const double axes_deg : {0.0, 30.0}) {
    const Sheet s = make_sheet(law, axes_deg, R0, F, R);
    for (int q = 0; q < 4; ++q) {
      const MembraneStress out = output(s, q);
      EXPECT_NEAR(out.max, sigma, 1e-12 * sigma);
      EXPECT_NEAR(out.min, 0.0, 1e-12 * sigma);
      const Vec3 ex = R * R0 * Vec3::UnitX(), ey = R * R0 * Vec3::UnitY();
      EXPECT_NEAR(std::abs(out.dir_max.dot(ex)), 1.0, 1e-12);
      EXPECT_NEAR(std::abs(out.dir_min.dot(ey)), 1.0, 1e-12);
      EXPECT_LT((out.sigma - sigma * ex * ex.transpose()).cwiseAbs().maxCoeff(), 1e-12 * sigma);
      // Sheet components in the deformed axes: a1 along F m1, a2 = n x a1.
      const double th = axes_deg * std::numbers::pi / 180;
      const Vec3 a1 = (R * R0 * F * Vec3(std::cos(th), std::sin(th), 0)).normalized();
      const Vec3 a2 = (R * R0 * Vec3::UnitZ()).cross(a1);
      EXPECT_NEAR(out.sheet[0], sigma * std::pow(a1.dot(ex), 2), 1e-12 * sigma);
      EXPECT_NEAR(out.sheet[1], sigma * std::pow(a2.dot(ex), 2), 1e-12 * sigma);
      EXPECT_NEAR(out.sheet[2], sigma * a1.dot(ex) * a2.dot(ex), 1e-12 * sigma);
      // Pure stretch along the principal material axes keeps them perpendicular only at 0 deg.
      if (axes_deg == 0.0) {
        EXPECT_NEAR(out.fiber_angle_change, 0.0, 1e-14);
      }
    }
  }
}

TEST(StressOutput, FiberAngleChangeUnderSimpleShear) {
  const auto law = PlaneStressLaw::fibers("net", {{100, 0}, {100, 90}});
  test::Random rnd(23);
  const Mat3 R0 = rnd.rotation(1.3), R = rnd.rotation(0.5);
  for (const double gamma : {0.05, 0.3, -0.6}) {
    Mat3 F = Mat3::Identity();
    F(0, 1) = gamma;  // x = X + γ Y
    for (const double axes_deg : {0.0, 30.0, 75.0}) {
      const double th = axes_deg * std::numbers::pi / 180;
      const Vec2 m1(std::cos(th), std::sin(th)), m2(-std::sin(th), std::cos(th));
      const Mat2 F2 = F.topLeftCorner<2, 2>();
      const Vec2 f1 = F2 * m1, f2 = F2 * m2;
      // Reference angle change from the in-plane vectors (atan2 of cross and dot).
      const double expected =
          std::atan2(f1.x() * f2.y() - f1.y() * f2.x(), f1.dot(f2)) - std::numbers::pi / 2;
      const Sheet s = make_sheet(law, axes_deg, R0, F, R);
      for (int q = 0; q < 4; ++q)
        EXPECT_NEAR(output(s, q).fiber_angle_change, expected, 1e-12)
            << "gamma " << gamma << " axes " << axes_deg;
      if (axes_deg == 0.0) {
        EXPECT_NEAR(expected, -std::atan(gamma), 1e-14);
      }
    }
  }
}

}  // namespace
}  // namespace velum
