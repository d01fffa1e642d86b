// Newton's line search and round-off floor on small systems with known solutions.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "dense_solver.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"

namespace velum {
namespace {

// Two uncoupled hardening springs k u + c u³ = load t, with an optional deterministic noise
// of amplitude `noise` whose sign alternates between evaluations (a force evaluation that
// cannot be exact) added to the residual and reported as the system's round-off level.
class CubicSprings final : public SecondOrderSystem {
 public:
  std::array<double, 2> k{1e-3, 1e-3}, c{1.0, 1.0}, load{1.0, 2.0}, noise{0.0, 0.0};
  double load_power = 1;  ///< the load grows as t^load_power
  int size() const override { return 2; }
  void evaluate(double t, const VecX& u, const VecX&, const VecX&, double cu, double, double,
                VecX& r, SparseMatrix* J) override {
    r.resize(2);
    ++evaluations_;
    for (int i = 0; i < 2; ++i) {
      r[i] = k[i] * u[i] + c[i] * u[i] * u[i] * u[i] - load[i] * std::pow(t, load_power);
      r[i] += noise[i] * (evaluations_ % 2 ? 1 : -1);
    }
    scale_ = std::pow(t, load_power) * std::hypot(load[0], load[1]);
    if (!J) return;
    ++tangents_;
    if (J->nonZeros() != 2) {
      J->resize(2, 2);
      J->setIdentity();
      J->makeCompressed();
    }
    for (int i = 0; i < 2; ++i) J->valuePtr()[i] = cu * (k[i] + 3 * c[i] * u[i] * u[i]);
  }
  const VecX& lumped_mass() const override { return mass_; }
  double force_scale() const override { return scale_; }
  double residual_noise() const override { return 2 * std::hypot(noise[0], noise[1]); }
  std::string diagnose_singular(const SparseMatrix&) const override { return {}; }

  int tangents() const { return tangents_; }  ///< evaluations that assembled J
  double root(int i) const {                  // k u + c u³ = load at t = 1, by bisection
    double lo = 0, hi = 10;
    for (int it = 0; it < 200; ++it) {
      const double m = 0.5 * (lo + hi);
      (k[i] * m + c[i] * m * m * m < load[i] ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
  }

 private:
  VecX mass_ = VecX::Ones(2);
  double scale_ = 0;
  int evaluations_ = 0, tangents_ = 0;
};

StepReport one_static_step(CubicSprings& sys, bool line_search, double tolerance, State& s,
                           bool reuse_tangent = false) {
  StaticNewton newton;
  newton.newton.line_search = line_search;
  newton.newton.tolerance = tolerance;
  newton.newton.max_iterations = 60;
  newton.newton.reuse_tangent = reuse_tangent;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  s.u = s.v = s.a = VecX::Zero(2);
  return newton.step(sys, *solver, 0.0, 1.0, s);
}

// From the stress-free start the tangent is k = 1e-3: the first full correction is 1000 times
// too long, and plain Newton creeps back at 2/3 per iteration on the cubic.
TEST(Newton, LineSearchCutsTheOvershootFromASoftStart) {
  CubicSprings a, b;
  State sa, sb;
  const StepReport plain = one_static_step(a, false, 1e-10, sa);
  const StepReport searched = one_static_step(b, true, 1e-10, sb);
  ASSERT_TRUE(plain.converged) << plain.reason;
  ASSERT_TRUE(searched.converged) << searched.reason;
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(sa.u[i], a.root(i), 1e-9);
    EXPECT_NEAR(sb.u[i], a.root(i), 1e-9);
  }
  EXPECT_GE(plain.iterations, 15);
  EXPECT_LE(searched.iterations, 10);
  EXPECT_LT(searched.iterations, plain.iterations / 2);
  // The default, with chord steps: where the tangent changes fast they are not taken (or are
  // followed by Newton steps), and the root is the same.
  CubicSprings c;
  State sc;
  const StepReport chord = one_static_step(c, true, 1e-10, sc, true);
  ASSERT_TRUE(chord.converged) << chord.reason;
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(sc.u[i], c.root(i), 1e-9);
  EXPECT_LE(chord.factorizations, searched.factorizations);
}

// A tolerance below the residual's round-off level is met at that level instead of failing.
// The noise sits on a stiff spring (as round-off of positions does on the in-plane stiffness
// of a sheet), so it hardly moves the solution of the soft one.
TEST(Newton, StopsAtTheRoundOffLevelOfTheResidual) {
  CubicSprings sys;
  sys.k = {1.0, 1e6};
  sys.c = {1.0, 0.0};
  sys.noise = {0.0, 1e-6};
  State s;
  const StepReport rep = one_static_step(sys, true, 1e-10, s);
  ASSERT_TRUE(rep.converged) << rep.reason;
  EXPECT_GT(rep.residuals.back(), 1e-10 * sys.force_scale());  // the plain target: not met
  EXPECT_LE(rep.residuals.back(), sys.residual_noise());
  EXPECT_LE(rep.iterations, 8);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(s.u[i], sys.root(i), 1e-10);
}

// Near the root Newton converges quadratically and the contraction bound on the distance left
// is loose: the run stops at the first iterate whose residual meets the tolerance and whose
// true distance to the root does, instead of paying for one more factorisation to confirm,
// and without assembling a tangent there.
TEST(Newton, StopsAtTheFirstIterateWithinTheTolerance) {
  CubicSprings sys;
  sys.k = {1.0, 1.0};
  const double tolerance = 1e-8;
  State s;
  const StepReport rep = one_static_step(sys, false, tolerance, s);
  ASSERT_TRUE(rep.converged) << rep.reason;
  const VecX root = (VecX(2) << sys.root(0), sys.root(1)).finished();
  EXPECT_LE((s.u - root).norm(), tolerance * root.norm());
  // The same Newton iterates, by hand: the first within the tolerance on both counts.
  VecX u = VecX::Zero(2), r(2);
  int first = 0;
  double ref = 0;
  for (int it = 0; it < 20; ++it, ++first) {
    for (int i = 0; i < 2; ++i) r[i] = sys.k[i] * u[i] + sys.c[i] * std::pow(u[i], 3) - sys.load[i];
    ref = std::max({ref, r.norm(), std::hypot(sys.load[0], sys.load[1])});
    if (it > 0 && r.norm() <= tolerance * ref && (u - root).norm() <= tolerance * u.norm()) break;
    for (int i = 0; i < 2; ++i) u[i] -= r[i] / (sys.k[i] + 3 * sys.c[i] * u[i] * u[i]);
  }
  EXPECT_EQ(rep.iterations, first);
  // One tangent per factorisation: none is assembled at the point where Newton stops.
  EXPECT_EQ(sys.tangents(), rep.iterations);
}

// Chord steps: once a correction has cut the residual tenfold, the factorisation at hand is
// reused. The root is the same to the tolerance, reached with fewer factorisations than full
// Newton takes, and every tangent assembled is factorised (none is wasted on a chord step).
TEST(Newton, ReusesTheTangentOnceTheResidualFallsFast) {
  CubicSprings full, chord;
  full.k = chord.k = {1.0, 1.0};
  State sf, sc;
  const StepReport a = one_static_step(full, false, 1e-10, sf, false);
  const StepReport b = one_static_step(chord, false, 1e-10, sc, true);
  ASSERT_TRUE(a.converged) << a.reason;
  ASSERT_TRUE(b.converged) << b.reason;
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(sc.u[i], chord.root(i), 1e-9 * chord.root(i));
  EXPECT_EQ(a.factorizations, a.iterations);
  EXPECT_LT(b.factorizations, b.iterations);
  EXPECT_LT(b.factorizations, a.factorizations);
  EXPECT_EQ(chord.tangents(), b.factorizations);
}

// Load steps on a path quadratic in time (linear springs, load ∝ t²): the line through the
// last two states misses the next one, the parabola through the last three hits it. The third
// step, with no record yet of which predictor does better, starts from the line; from the
// fourth on the parabola starts in equilibrium and no correction is needed.
TEST(Newton, PredictsAlongTheParabolaWhenItDidBetter) {
  CubicSprings sys;
  sys.k = {1.0, 2.0};
  sys.c = {0.0, 0.0};
  sys.load_power = 2;
  StaticNewton stepper;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  State s;
  s.u = s.v = s.a = VecX::Zero(2);
  std::vector<StepReport> reps;
  for (int k = 0; k < 6; ++k) {
    reps.push_back(stepper.step(sys, *solver, 0.1 * k, 0.1, s));
    ASSERT_TRUE(reps.back().converged) << reps.back().reason;
  }
  const double t2 = 0.6 * 0.6;  // the load factor at the end
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(s.u[i], sys.load[i] * t2 / sys.k[i], 1e-12);
  EXPECT_GE(reps[2].iterations, 1);  // the line: off by the second difference
  for (int k = 3; k < 6; ++k) {
    EXPECT_EQ(reps[k].iterations, 0) << "step " << k + 1;
    EXPECT_LT(reps[k].residuals.front(), 1e-12) << "step " << k + 1;
  }
}

// A solver whose first step alone (solve_within with an infinite residual) is its exact
// solution scaled by `pass_factor`, which reports `reported` as that step's accuracy: an
// honest one (factor 1 + 1e-3, reported 1e-3), one that says nothing (NaN), and one that lies
// (a step of zero, reported 1e-3).
class OnePassSolver final : public test::DenseSolver {
 public:
  double pass_factor = 1, reported = 0;
  int passes = 0, checked = 0;  ///< solves of the first step alone; the others
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    ++checked;
    return DenseSolver::solve(b, x);
  }
  bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) override {
    if (!std::isinf(residual)) return solve(b, x);
    ++passes;
    x = pass_factor * lu_.solve(b);
    return true;
  }
  double one_pass_accuracy() const override { return reported; }
};

// Far from the root (above ten targets) Newton takes the solver's first step alone while its
// reported accuracy is within 1e-2 (the honest solver: every correction, the same count as
// exact solves); a step that does not halve the residual (the lying solver's zero step) turns
// the checks back on for the rest of the step. Every run converges to the root.
TEST(Newton, TakesTheSolversFirstStepAloneWhileItHalvesTheResidual) {
  struct Case {
    double factor, reported;
  };
  // The solver that reports nothing first: its solves are all exact, the count to match.
  int exact_iterations = -1;
  for (const Case c : {Case{1, std::nan("")}, Case{1 + 1e-3, 1e-3}, Case{0, 1e-3}}) {
    CubicSprings sys;  // mildly hardening: every exact Newton correction halves the residual
    sys.k = {1.0, 1.0};
    sys.c = {0.1, 0.1};
    StaticNewton newton;
    newton.newton.tolerance = 1e-10;
    newton.newton.max_iterations = 60;
    newton.newton.line_search = false;
    OnePassSolver solver;
    solver.pass_factor = c.factor;
    solver.reported = c.reported;
    State s;
    s.u = s.v = s.a = VecX::Zero(2);
    const StepReport rep = newton.step(sys, solver, 0.0, 1.0, s);
    ASSERT_TRUE(rep.converged) << rep.reason;
    for (int i = 0; i < 2; ++i) EXPECT_NEAR(s.u[i], sys.root(i), 1e-9);
    if (std::isnan(c.reported)) {
      EXPECT_EQ(solver.passes, 0);
      exact_iterations = rep.iterations;
    } else if (c.factor == 0) {
      EXPECT_EQ(solver.passes, 1);  // then checked: one correction lost
      EXPECT_LE(rep.iterations, exact_iterations + 1);
    } else {
      EXPECT_EQ(solver.passes, rep.iterations);  // every correction far from the root
      EXPECT_LE(rep.iterations, exact_iterations);
    }
  }
}

// A solver that records what each solve is asked for (the linear residual allowed against
// the right-hand side's norm) and reports its first step's accuracy as not measured (NaN)
// until it has solved once, as a float factor does, then as 0.05 (too loose for unchecked
// first steps: every correction is a checked solve).
class RecordingSolver final : public test::DenseSolver {
 public:
  std::vector<double> asked;  ///< residual allowed / ‖b‖, per solve_within
  bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) override {
    asked.push_back(residual / b.norm());
    return solve(b, x);
  }
  double one_pass_accuracy() const override { return asked.empty() ? std::nan("") : 0.05; }
};

// Far from the root, while the solver's first step is not measured, a correction asks for half
// the residual (Eisenstat and Walker's first forcing term) instead of a thousandth: a float
// factor whose refinement stalls on a badly conditioned first tangent is then not replaced by
// a double one for a correction the line search cuts anyway. Once the solver has measured its
// step, the corrections are held to a thousandth as before; the root is the same.
TEST(Newton, AsksForHalfTheResidualOfAnUnmeasuredSolverFarFromTheRoot) {
  CubicSprings sys;
  sys.k = {1.0, 1.0};
  sys.c = {0.1, 0.1};
  StaticNewton newton;
  newton.newton.tolerance = 1e-10;
  newton.newton.line_search = false;
  newton.newton.reuse_tangent = false;
  RecordingSolver solver;
  State s;
  s.u = s.v = s.a = VecX::Zero(2);
  const StepReport rep = newton.step(sys, solver, 0.0, 1.0, s);
  ASSERT_TRUE(rep.converged) << rep.reason;
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(s.u[i], sys.root(i), 1e-9);
  ASSERT_GE(solver.asked.size(), 3U);
  EXPECT_NEAR(solver.asked.front(), 0.5, 1e-12);
  for (std::size_t k = 1; k < solver.asked.size(); ++k)
    EXPECT_LE(solver.asked[k], 1e-3 * (1 + 1e-12)) << "solve " << k;
}

// Newton on u³ − 2u + 2 = 0 from u = 0 cycles between 0 and 1 for ever (the textbook cycle):
// it must stop as stagnated long before a large max_iterations, not run it out.
class NewtonCycle final : public SecondOrderSystem {
 public:
  int size() const override { return 1; }
  void evaluate(double t, const VecX& u, const VecX&, const VecX&, double cu, double, double,
                VecX& r, SparseMatrix* J) override {
    r.resize(1);
    r[0] = u[0] * u[0] * u[0] - 2 * u[0] + 2 * t;
    if (!J) return;
    if (J->nonZeros() != 1) {
      J->resize(1, 1);
      J->setIdentity();
      J->makeCompressed();
    }
    J->valuePtr()[0] = cu * (3 * u[0] * u[0] - 2);
  }
  const VecX& lumped_mass() const override { return mass_; }
  double force_scale() const override { return 2; }
  double residual_noise() const override { return 0; }
  std::string diagnose_singular(const SparseMatrix&) const override { return {}; }

 private:
  VecX mass_ = VecX::Ones(1);
};

TEST(Newton, StopsWhenTheResidualStagnates) {
  NewtonCycle sys;
  StaticNewton newton(false);  // no predictor: the step starts at u = 0
  newton.newton.line_search = false;
  newton.newton.max_iterations = 1000;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  State s;
  s.u = s.v = s.a = VecX::Zero(1);
  const StepReport rep = newton.step(sys, *solver, 0.0, 1.0, s);
  EXPECT_FALSE(rep.converged);
  EXPECT_NE(rep.reason.find("stagnated"), std::string::npos) << rep.reason;
  EXPECT_LT(rep.residuals.size(), 60U);
}

}  // namespace
}  // namespace velum
