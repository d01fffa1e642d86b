// The one convergence test of the time room's nonlinear solves, and the Newton solver that
// applies it: on its own numbers, and through NewtonSolver on small systems.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dense_solver.hpp"
#include "velum/time/newton.hpp"

namespace velum {
namespace {

TEST(ConvergenceTest, JudgesTheResidualAgainstTheLargestForceSeen) {
  ConvergenceTest test(1e-8, 1e-12);
  EXPECT_DOUBLE_EQ(test.residual_target(1e3, 10.0, 0.0), 1e-5);  // the residual itself
  EXPECT_DOUBLE_EQ(test.residual_target(1.0, 10.0, 0.0), 1e-5);  // the reference is kept
  EXPECT_DOUBLE_EQ(test.reference(), 1e3);
  EXPECT_DOUBLE_EQ(test.residual_target(1.0, 1e4, 0.0), 1e-4);   // a larger force scale
  EXPECT_DOUBLE_EQ(test.residual_target(1.0, 1e4, 1e-3), 1e-3);  // the round-off level
  test.restart();
  EXPECT_DOUBLE_EQ(test.residual_target(0.0, 0.0, 0.0), 1e-12);  // the absolute floor
  // A given scale (dynamic relaxation's): no reference kept.
  EXPECT_DOUBLE_EQ(test.target_against(1e6, 0.0), 1e-2);
  EXPECT_DOUBLE_EQ(test.reference(), 0.0);
}

TEST(ConvergenceTest, AsksForBothTheResidualAndTheDistance) {
  const ConvergenceTest test(1e-8, 1e-12);
  // The distance against the step's change, never below the position's round-off.
  EXPECT_DOUBLE_EQ(test.distance_target(2.0, 1.0), 2e-8);
  EXPECT_DOUBLE_EQ(test.distance_target(0.0, 1.0), 2e-14);
  EXPECT_TRUE(ConvergenceTest::met(1e-6, 1e-5, 1e-9, 2e-8));
  EXPECT_FALSE(ConvergenceTest::met(1e-4, 1e-5, 1e-9, 2e-8));  // the residual too large
  EXPECT_FALSE(ConvergenceTest::met(1e-6, 1e-5, 1e-7, 2e-8));  // the distance too large
  // A residual that stopped falling within 1000 targets is at its round-off floor.
  EXPECT_TRUE(ConvergenceTest::at_floor(1e-3, 1.5e-3, 1e-5));
  EXPECT_FALSE(ConvergenceTest::at_floor(1e-3, 3e-3, 1e-5));    // still halving
  EXPECT_FALSE(ConvergenceTest::at_floor(1e-1, 1.5e-1, 1e-5));  // far above the target
}

// r(u) = A u³ + u − b componentwise, or (singular) r = u_0 + u_1 − 1 twice.
class Springs final : public SecondOrderSystem {
 public:
  bool singular = false;
  int size() const override { return 2; }
  void evaluate(double, const VecX& u, const VecX&, const VecX&, double cu, double, double, VecX& r,
                SparseMatrix* J) override {
    r.resize(2);
    for (int i = 0; i < 2; ++i)
      r[i] = singular ? u[0] + u[1] - 1 : u[i] * u[i] * u[i] + u[i] - (i + 1.0);
    if (!J) return;
    J->resize(2, 2);
    J->setZero();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        if (singular || i == j) J->insert(i, j) = cu * (singular ? 1.0 : 3 * u[i] * u[i] + 1);
    J->makeCompressed();
  }
  const VecX& lumped_mass() const override { return mass_; }
  double force_scale() const override { return 3; }
  std::string diagnose_singular(const SparseMatrix&) const override { return {}; }

 private:
  VecX mass_ = VecX::Ones(2);
};

// A dense LU that refuses a singular matrix, as the sparse solvers do.
class CheckedSolver final : public test::DenseSolver {
 public:
  bool factorize(const SparseMatrix& A) override {
    DenseSolver::factorize(A);
    return std::abs(lu_.determinant()) > 1e-12;
  }
};

StepReport solve(Springs& sys, VecX& u, NewtonSettings ns = {}) {
  CheckedSolver dense;
  LowRankCorrectedSolver solver(dense, sys);
  NewtonWork work;
  const VecX start = VecX::Zero(2);
  u = start;
  return NewtonSolver(sys, solver, ns)
      .solve(
          start, u, work,
          [&](const VecX& x, VecX& r, SparseMatrix* J) { sys.evaluate(0, x, x, x, 1, 0, 0, r, J); },
          {.line_search_by_default = true});
}

TEST(NewtonSolver, ConvergesUnderTheTest) {
  Springs sys;
  VecX u;
  const StepReport rep = solve(sys, u);
  ASSERT_TRUE(rep.converged) << rep.reason;
  EXPECT_NEAR(u[0] * u[0] * u[0] + u[0], 1.0, 1e-8 * 3);
  EXPECT_NEAR(u[1] * u[1] * u[1] + u[1], 2.0, 1e-8 * 3);
  EXPECT_LE(rep.residuals.back(), 1e-8 * 3);  // against the force scale, the largest force
}

TEST(NewtonSolver, ReturnsAFailureAsAStatus) {
  Springs sys;
  sys.singular = true;
  VecX u;
  StepReport rep;
  EXPECT_NO_THROW(rep = solve(sys, u));
  EXPECT_FALSE(rep.converged);
  EXPECT_NE(rep.reason.find("factorisation failed"), std::string::npos) << rep.reason;
  Springs slow;
  NewtonSettings one;
  one.max_iterations = 1;
  EXPECT_NO_THROW(rep = solve(slow, u, one));
  EXPECT_FALSE(rep.converged);
  EXPECT_NE(rep.reason.find("did not converge in 1 iterations"), std::string::npos) << rep.reason;
}

}  // namespace
}  // namespace velum
