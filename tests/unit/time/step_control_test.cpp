// The step size after cut-backs: it grows back to the nominal step, after easy steps and after
// a streak of hard ones alike (a blown-up airbag stayed at its cut step for 13,674 steps).
#include <gtest/gtest.h>

#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

// A one-equation system nobody evaluates: the integrator below decides alone.
class Nothing final : public SecondOrderSystem {
 public:
  int size() const override { return 1; }
  void evaluate(double, const VecX&, const VecX&, const VecX&, double, double, double, VecX& r,
                SparseMatrix*) override {
    r = VecX::Zero(1);
  }
  const VecX& lumped_mass() const override { return m_; }
  double force_scale() const override { return 1; }
  std::string diagnose_singular(const SparseMatrix&) const override { return {}; }

 private:
  VecX m_ = VecX::Ones(1);
};

// Steps longer than `allowed` inside [t_hard, t_hard + width) fail; every converged step
// reports `factorizations` (above the easy count: a hard step).
class Picky final : public TimeIntegrator {
 public:
  double t_hard = 0.3, width = 0.01, allowed = 1e-3;
  int factorizations = 6;
  std::string name() const override { return "picky"; }
  StepReport step(SecondOrderSystem&, LinearSolver&, double t, double h, State&) override {
    StepReport rep;
    rep.converged = !(t + h > t_hard && t < t_hard + width && h > allowed);
    rep.iterations = rep.factorizations = factorizations;
    return rep;
  }
  StepReport start(SecondOrderSystem&, LinearSolver&, double, State&) override {
    StepReport rep;
    rep.converged = true;
    return rep;
  }
};

struct Steps {
  TimeLoopResult loop;
  std::vector<double> h;
  std::vector<double> t;
};

Steps run(Picky& picky) {
  Nothing sys;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  TimeLoopSettings cfg;
  cfg.t_end = 1, cfg.step = 0.01, cfg.min_step = 1e-8;
  State s;
  s.u = s.v = s.a = VecX::Zero(1);
  Steps out;
  out.loop = run_time_loop(sys, picky, *solver, cfg, s, [&](const AcceptedStep& st, const State&) {
    out.h.push_back(st.h);
    out.t.push_back(st.t);
    return true;
  });
  return out;
}

// After the hard window the step is back to nominal within a few doublings, hard steps or not.
void expect_regrown(const Steps& r, double window_end) {
  ASSERT_TRUE(r.loop.completed) << r.loop.reason;
  EXPECT_GT(r.loop.cutbacks, 0);
  int after = 0;
  for (size_t i = 0; i < r.t.size(); ++i)
    if (r.t[i] > window_end + 0.2 && r.t[i] < 1 - 1e-9) {  // the last step lands on t_end
      EXPECT_NEAR(r.h[i], 0.01, 1e-12) << "t = " << r.t[i];
      ++after;
    }
  EXPECT_GT(after, 40);
  // Bounded: the window at its step, the rest at the nominal one, and the way up.
  EXPECT_LT(r.loop.steps, 10 + 70 + 100 + 60);
}

TEST(StepControl, RegrowsAfterEasySteps) {
  Picky picky;
  picky.factorizations = 1;
  expect_regrown(run(picky), picky.t_hard + picky.width);
}

TEST(StepControl, RegrowsAfterAStreakOfHardSteps) {
  Picky picky;
  picky.factorizations = 6;  // above easy_iterations = 4 at every size
  const Steps r = run(picky);
  expect_regrown(r, picky.t_hard + picky.width);
  std::cout << r.loop.steps << " steps, " << r.loop.cutbacks << " cut-backs\n";
}

}  // namespace
}  // namespace velum
