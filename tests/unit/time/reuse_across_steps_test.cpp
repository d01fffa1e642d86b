// Dynamics with the last step's factorisation carried into the next step (newton
// .reuse_across_steps): same answers to the tolerance, fewer factorisations, a fresh one as
// soon as the chord steps stop converging fast or the step size changes.
#include <gtest/gtest.h>

#include <cmath>

#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"

namespace velum {
namespace {

// Two uncoupled hardening (Duffing) oscillators m a + k u + c u³ = f(t), f = F sin(ω t), plus
// a load jump of `kick` at t >= t_kick (a step the old tangent cannot take).
class Duffing final : public SecondOrderSystem {
 public:
  double m = 1, k = 40, c = 400, F = 3, omega = 5, kick = 0, t_kick = 1e30;
  int size() const override { return 2; }
  void evaluate(double t, const VecX& u, const VecX&, const VecX& a, double cu, double, double ca,
                VecX& r, SparseMatrix* J) override {
    r.resize(2);
    const double f = F * std::sin(omega * t) + (t >= t_kick ? kick : 0.0);
    for (int i = 0; i < 2; ++i) r[i] = m * a[i] + k * u[i] + c * u[i] * u[i] * u[i] - (i + 1) * f;
    scale_ = std::abs(f) * 3 + 1e-3;
    if (!J) return;
    if (J->nonZeros() != 2) {
      J->resize(2, 2);
      J->setIdentity();
      J->makeCompressed();
    }
    for (int i = 0; i < 2; ++i) J->valuePtr()[i] = cu * (k + 3 * c * u[i] * u[i]) + ca * m;
  }
  const VecX& lumped_mass() const override { return mass_; }
  double force_scale() const override { return scale_; }
  double residual_noise() const override { return 0; }
  std::string diagnose_singular(const SparseMatrix&) const override { return {}; }

 private:
  VecX mass_ = VecX::Ones(2);
  double scale_ = 1;
};

struct Motion {
  State s;
  int iterations = 0, factorizations = 0;
  std::vector<int> per_step;  ///< factorisations of each step
};

// Steps of size h (h_late from step `switch_at` on) from rest to `steps`.
Motion integrate(Duffing& sys, bool reuse, int steps, double h, double h_late = 0,
                 int switch_at = -1) {
  auto integrator = GeneralizedAlpha::newmark();
  integrator->newton.tolerance = 1e-10;
  integrator->newton.reuse_across_steps = reuse;
  auto solver = make_linear_solver(SolverKind::kKlu);
  Motion run;
  run.s.u = run.s.v = VecX::Zero(2);
  EXPECT_TRUE(integrator->start(sys, *solver, 0.0, run.s).converged);
  double t = 0;
  for (int n = 0; n < steps; ++n) {
    const double dt = switch_at >= 0 && n >= switch_at ? h_late : h;
    const StepReport rep = integrator->step(sys, *solver, t, dt, run.s);
    EXPECT_TRUE(rep.converged) << rep.reason;
    if (!rep.converged) break;
    t += dt;
    run.iterations += rep.iterations;
    run.factorizations += rep.factorizations;
    run.per_step.push_back(rep.factorizations);
  }
  return run;
}

TEST(ReuseAcrossSteps, SameMotionWithFewerFactorisations) {
  Duffing a, b;
  const Motion fresh = integrate(a, false, 200, 0.005);
  const Motion carried = integrate(b, true, 200, 0.005);
  for (int i = 0; i < 2; ++i) {
    // Each step converged to 1e-10 of its change either way: the motions agree to that order.
    EXPECT_NEAR(carried.s.u[i], fresh.s.u[i], 1e-8 * (1 + std::abs(fresh.s.u[i])));
    EXPECT_NEAR(carried.s.v[i], fresh.s.v[i], 1e-7 * (1 + std::abs(fresh.s.v[i])));
  }
  EXPECT_GT(std::abs(fresh.s.u[1]), 1e-3);  // it moved
  EXPECT_GE(fresh.factorizations, 200);     // every step factorised at least once
  EXPECT_LT(carried.factorizations, fresh.factorizations / 2);
  EXPECT_EQ(carried.per_step[0], fresh.per_step[0]);  // nothing to carry into the first step
}

// A load jump: the chord step from the old tangent does not cut the residual tenfold, so the
// very next correction is a Newton one; the step converges as without the reuse.
TEST(ReuseAcrossSteps, FallsBackToAFreshTangentAtOnceInAHardStep) {
  // A stiff cubic: the jump moves the springs where 3 c u² outweighs the mass's m/(β h²).
  Duffing a, b;
  a.c = b.c = 1e7;
  a.kick = b.kick = 1e5;
  a.t_kick = b.t_kick = 0.0975;
  const Motion fresh = integrate(a, false, 40, 0.005);
  const Motion carried = integrate(b, true, 40, 0.005);
  const int kick_step = 19;  // the first step whose end (0.1) is past t_kick
  ASSERT_EQ(carried.per_step.size(), 40u);
  EXPECT_GE(carried.per_step[kick_step], 1);
  EXPECT_LE(carried.per_step[kick_step], fresh.per_step[kick_step]);
  for (int i = 0; i < 2; ++i)
    EXPECT_NEAR(carried.s.u[i], fresh.s.u[i], 1e-8 * (1 + std::abs(fresh.s.u[i])));
}

// The Jacobian is shifted by the mass over the step size squared: a factorisation made for
// another step size is never carried.
TEST(ReuseAcrossSteps, NotCarriedAcrossAChangeOfStepSize) {
  Duffing a;
  const Motion run = integrate(a, true, 30, 0.005, 0.0025, 20);
  ASSERT_EQ(run.per_step.size(), 30u);
  EXPECT_EQ(run.per_step[19], 0);  // carried (the motion is smooth at this step size)
  EXPECT_GE(run.per_step[20], 1);  // the first step of the new size factorises
}

}  // namespace
}  // namespace velum
