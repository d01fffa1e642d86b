// Output quantities of a membrane point (THEORY §9): true stress and principal directions under
// a uniaxial stress state, and the change of the angle between the material directions under
// simple shear.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support.hpp"
#include "velum/element/membrane.hpp"
#include "velum/element/stress_output.hpp"
#include "velum/model/element_block.hpp"

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

// Issue 20: a block's output at any ξ is the state the element integrates there (the reference
// metric, the sheet axes projected onto the tangent plane at ξ, the law): at every integration
// point of a curved tri6 it equals the kernel's own point stress; strain and stretches follow
// from the same point's metric.
TEST(StressOutput, BlockOutputAtAPointIsThatPointsState) {
  using T6 = Membrane<shape::Tri6>;
  const auto law = PlaneStressLaw::orthotropic("ortho", 1000, 400, 0.3, 150, false);
  // A curved element: six nodes on a sphere of radius 2, deformed by a non-uniform map.
  T6::Nodes X, x;
  const double xi[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  for (int n = 0; n < 6; ++n) {
    const double u = 0.6 * xi[n][0], v = 0.6 * xi[n][1];
    X.col(n) = Vec3(u, v, std::sqrt(4 - u * u - v * v));
    const Vec3 P = X.col(n);
    x.col(n) =
        P + Vec3(0.08 * P.x() + 0.03 * P.y() * P.y(), -0.02 * P.x() * P.y(), 0.05 * P.x() * P.x());
  }
  const SheetAxes axes = test::axes_at(35.0, Mat3::Identity());
  T6::Points pts;
  T6::setup(X, law.Q(), axes, 0.01, pts);
  NodePositions Xall = X, xall = x;
  BlockSetupReport report;
  const auto block = make_membrane_block("tri6", "s", {0, 1, 2, 3, 4, 5}, Xall, SheetLaw(law), 1.0,
                                         0.01, &axes, shape::Integration::kGauss, report);
  const auto rule = shape::Tri6::rule();
  for (int q = 0; q < shape::Tri6::kPoints; ++q) {
    Vec3 e, S;
    Eigen::Matrix<double, 3, 2> g;
    T6::strain_stress(pts, q, x, e, S, g);
    const MembraneStress ref = membrane_stress(g, S, pts[q].G, pts[q].T);
    const MembraneStress out = block->output_at(0, {rule.xi[q][0], rule.xi[q][1]}, xall);
    const double scale = std::abs(ref.max) + std::abs(ref.min);
    EXPECT_GT(scale, 1.0);
    EXPECT_NEAR(out.max, ref.max, 1e-10 * scale) << q;
    EXPECT_NEAR(out.min, ref.min, 1e-10 * scale) << q;
    EXPECT_LT((out.sheet - ref.sheet).norm(), 1e-10 * scale) << q;
    EXPECT_LT((out.strain - ref.strain).norm(), 1e-13) << q;
    // E in the sheet axes from the convected strain e = [γ11, γ22, 2γ12]: E = A e.
    const Vec3 E = sheet_strain_map(pts[q].T) * e;
    EXPECT_LT((ref.strain - Vec3(E[0], E[1], 0.5 * E[2])).norm(), 1e-13) << q;
    // Principal stretches: the eigenvalues of C = I + 2E are their squares.
    Mat2 C;
    C << 1 + 2 * E[0], E[2], E[2], 1 + 2 * E[1];
    EXPECT_NEAR(out.stretch_max * out.stretch_max + out.stretch_min * out.stretch_min, C.trace(),
                1e-12);
    EXPECT_NEAR(std::pow(out.stretch_max * out.stretch_min, 2), C.determinant(), 1e-12);
    // Deformed axes: a1 along F m1, a2 = n x a1, n the deformed normal; fibre 2 along F m2.
    EXPECT_NEAR(out.axis1.dot(out.normal), 0, 1e-14);
    EXPECT_NEAR(out.axis2.dot(out.axis1), 0, 1e-14);
    EXPECT_NEAR(out.normal.dot(g.col(0)), 0, 1e-13);
    EXPECT_NEAR(out.fiber2.norm(), 1, 1e-14);
  }
  // The centre of the element is not a point of the 6-point rule: there the
  // output comes from the centre's own metric, not a neighbour's.
  const MembraneStress centre = block->output(0, xall).stress;
  const MembraneStress at = block->output_at(0, {1.0 / 3, 1.0 / 3}, xall);
  EXPECT_EQ(centre.max, at.max);
  EXPECT_EQ(block->output(0, xall).thickness, 0.01);
}

}  // namespace
}  // namespace velum
