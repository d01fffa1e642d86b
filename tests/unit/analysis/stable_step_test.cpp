// The stable step of central difference (time/stable_step.hpp) against the largest
// eigenvalue of M⁻¹K computed densely, on a small anisotropic prestressed sheet with a cable
// across it: at the start (the assembled tangent) and from the current state (the forces'
// directional differences), and the Gershgorin row bounds mass scaling uses.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "unit_square.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/model/model.hpp"
#include "velum/time/stable_step.hpp"

namespace velum {
namespace {

// A 3 x 3 quad4 square (1 m) clamped at its edges: fibre families at 25°, 115° and 70° of
// different stiffness (anisotropic in the sheet's axes), prestressed unequally, and a cable
// across its middle row of nodes, stiffer along its line than the sheet.
Model anisotropic_sheet() {
  Model m;
  test::UnitSquare sq = test::add_unit_square(m, 3);
  LinearSheetLaw law(PlaneStressLaw::fibers(
      "fabric",
      {{.E = 3e9, .angle_deg = 25}, {.E = 1e9, .angle_deg = 115}, {.E = 0.4e9, .angle_deg = 70}}));
  law.with_prestress(Vec3(2e6, 1e6, 0.3e6));
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block("quad4", "sheet", std::move(sq.conn), m.X, law, 1000.0,
                                         1e-3, nullptr, shape::Integration::kGauss, report));
  m.blocks.push_back(make_cable_block(
      "cable2", "line", {sq.id(0, 1), sq.id(1, 1), sq.id(1, 1), sq.id(2, 1)}, m.X,
      CableLaw{.E = 1e11, .S0 = 1e7}, 7800.0, 1e-5, shape::Integration::kGauss, report));
  m.fixed.push_back({sq.edge, {true, true, true}});
  return m;
}

// The largest eigenvalue of M⁻¹K at (u, v = 0), K the Jacobian (c_u = 1), densely; K's
// asymmetry is checked to be round-off.
double dense_omega_squared(MechanicalSystem& sys, const VecX& u) {
  VecX r;
  SparseMatrix K;
  const VecX zero = VecX::Zero(sys.size());
  sys.evaluate(0, u, zero, zero, 1.0, 0, 0, r, &K);
  const MatX Kd = MatX(K);
  EXPECT_LT((Kd - Kd.transpose()).norm(), 1e-9 * Kd.norm());
  const VecX s = sys.lumped_mass().cwiseSqrt().cwiseInverse();
  const MatX A = s.asDiagonal() * (0.5 * (Kd + Kd.transpose())) * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<MatX> eig(A, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().maxCoeff();
}

// A displaced state: the sheet bulged and sheared (up to a tenth of its size), at rest, with
// the acceleration its residual gives (what central difference leaves after a step).
State displaced(MechanicalSystem& sys, const Model& m, double amplitude) {
  NodePositions U = NodePositions::Zero(3, m.num_nodes());
  for (int k = 0; k < m.num_nodes(); ++k) {
    const double x = m.X(0, k), y = m.X(1, k);
    const double bump = std::sin(M_PI * x) * std::sin(M_PI * y);
    U.col(k) = amplitude * Vec3(0.3 * bump * y, 0.2 * bump * x, bump);
  }
  State s;
  s.u = VecX::Zero(sys.size());
  sys.dofs().gather(U, s.u);
  s.v = VecX::Zero(sys.size());
  VecX r;
  sys.evaluate(0, s.u, s.v, s.v, 0, 0, 0, r, nullptr);
  s.a = -r.cwiseQuotient(sys.lumped_mass());
  return s;
}

TEST(StableStep, TheStartEstimateIsWithinAPercentOfTheLargestEigenvalueAndBelowIt) {
  const Model m = anisotropic_sheet();
  MechanicalSystem sys(m);
  const State s = displaced(sys, m, 0.05);
  const double exact = dense_omega_squared(sys, s.u);
  StableStepEstimate e;
  const double h = e.start(sys, 0, s);
  const double est = e.omega_squared();
  std::printf("start: ω² %.6e, dense %.6e, ratio %.6f\n", est, exact, est / exact);
  EXPECT_LE(est, exact * (1 + 1e-10));  // a power iteration's norm ratio: from below
  EXPECT_GE(est, 0.99 * exact);
  EXPECT_DOUBLE_EQ(h, 2 / std::sqrt(est));
}

TEST(StableStep, TheUpdateFollowsTheCurrentStateToWithinAPercent) {
  // From the start's vector at a slightly bulged sheet to a state bulged ten times more,
  // where the stiffness has changed: the updates (force differences, a few iterations each)
  // reach the dense eigenvalue there.
  const Model m = anisotropic_sheet();
  MechanicalSystem sys(m);
  StableStepEstimate e;
  e.start(sys, 0, displaced(sys, m, 0.01));
  const double before = e.omega_squared();
  const State s = displaced(sys, m, 0.1);
  const double exact = dense_omega_squared(sys, s.u);
  ASSERT_GT(std::abs(exact - before), 0.02 * exact);  // the state changed the answer
  double est = 0;
  for (int k = 0; k < 5; ++k) {
    e.update(sys, 0, 0.0, s);
    est = e.omega_squared();
  }
  std::printf("update: ω² %.6e, dense %.6e (before %.6e), ratio %.6f, %ld evaluations\n", est,
              exact, before, est / exact, e.evaluations());
  EXPECT_LE(est, exact * (1 + 1e-5));  // the differences' truncation error
  EXPECT_GE(est, 0.99 * exact);
  EXPECT_LE(e.evaluations(), 5 * StableStepEstimate::kMaxIterations);
}

TEST(StableStep, GershgorinRowsBoundTheLargestEigenvalue) {
  const Model m = anisotropic_sheet();
  MechanicalSystem sys(m);
  const State s = displaced(sys, m, 0.05);
  const double exact = dense_omega_squared(sys, s.u);
  StableStepEstimate e;
  e.start(sys, 0, s);
  const VecX g = stiffness_row_bounds(e.stiffness(), sys.jacobian_low_rank());
  const double bound = g.cwiseQuotient(sys.lumped_mass()).maxCoeff();
  std::printf("Gershgorin: %.6e, dense %.6e, ratio %.3f\n", bound, exact, bound / exact);
  EXPECT_GE(bound, exact);
  EXPECT_LT(bound, 10 * exact);  // a bound, not a wild one
}

}  // namespace
}  // namespace velum
