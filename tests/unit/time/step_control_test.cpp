// The step size after cut-backs: it grows back to the nominal step, after easy steps and after
// a streak of hard ones alike (a blown-up airbag stayed at its cut step for 13,674 steps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

// A fixed step of 0.005 to t = 5000 with output every 50: a million steps, each output time
// and the end reached exactly (the summed time once fell 2.6e-11 short of t = 100 and asked
// for a step of that size), no step below min_step, every step the nominal one.
TEST(StepControl, KeepsTimeWithoutDriftOverAMillionSteps) {
  Nothing sys;
  Picky never_hard;
  never_hard.t_hard = 1e300;
  never_hard.factorizations = 1;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  TimeLoopSettings cfg;
  cfg.t_end = 5000, cfg.step = 0.005, cfg.min_step = 1e-8, cfg.adaptive = false;
  cfg.output_interval = 50;
  State s;
  s.u = s.v = s.a = VecX::Zero(1);
  double smallest = 1, largest = 0, worst = 0;
  int outputs = 0;
  const TimeLoopResult r =
      run_time_loop(sys, never_hard, *solver, cfg, s, [&](const AcceptedStep& st, const State&) {
        smallest = std::min(smallest, st.h), largest = std::max(largest, st.h);
        // Where the step ends against the count times the step: no drift.
        worst = std::max(worst, std::abs(st.t - st.step * cfg.step));
        if (st.output_time) {
          ++outputs;
          EXPECT_EQ(st.t, 50.0 * outputs) << "step " << st.step;
        }
        return true;
      });
  ASSERT_TRUE(r.completed) << r.reason;
  EXPECT_EQ(r.steps, 1000000);
  EXPECT_EQ(r.t, 5000.0);
  EXPECT_EQ(outputs, 100);
  EXPECT_GE(smallest, cfg.min_step);
  EXPECT_NEAR(smallest, cfg.step, 1e-9 * cfg.step);
  EXPECT_NEAR(largest, cfg.step, 1e-9 * cfg.step);
  EXPECT_LT(worst, 1e-11);
}

// A step that would stop a sliver short of an output time is stretched to land on it; a
// genuine remainder (a third of a step) is a step of its own.
TEST(StepControl, MergesASliverIntoTheStepBefore) {
  Nothing sys;
  Picky never_hard;
  never_hard.t_hard = 1e300;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  TimeLoopSettings cfg;
  cfg.t_end = 1, cfg.step = 0.1 - 1e-10, cfg.min_step = 1e-8, cfg.adaptive = false;
  State s;
  s.u = s.v = s.a = VecX::Zero(1);
  std::vector<double> h;
  TimeLoopResult r =
      run_time_loop(sys, never_hard, *solver, cfg, s, [&](const AcceptedStep& st, const State&) {
        h.push_back(st.h);
        return true;
      });
  ASSERT_TRUE(r.completed) << r.reason;
  EXPECT_EQ(h.size(), 10u);  // not 10 steps and a sliver of 1e-9
  EXPECT_GE(*std::min_element(h.begin(), h.end()), cfg.min_step);
  cfg.step = 0.3;
  h.clear();
  r = run_time_loop(sys, never_hard, *solver, cfg, s, [&](const AcceptedStep& st, const State&) {
    h.push_back(st.h);
    return true;
  });
  ASSERT_TRUE(r.completed) << r.reason;
  ASSERT_EQ(h.size(), 4u);
  EXPECT_NEAR(h.back(), 0.1, 1e-12);
}

// An end lost in the start's last digits (a stage of 1e-300 after t = 100) solves nothing:
// that is no converged run.
TEST(StepControl, AnEndTooCloseToTheStartIsNoRun) {
  Nothing sys;
  Picky never_hard;
  auto solver = make_linear_solver(SolverKind::kUmfpack);
  TimeLoopSettings cfg;
  cfg.t0 = 100, cfg.t_end = 100 + 1e-300, cfg.step = 1e-300;
  State s;
  s.u = s.v = s.a = VecX::Zero(1);
  cfg.t_end = std::nextafter(100.0, 200.0);
  const TimeLoopResult r = run_time_loop(sys, never_hard, *solver, cfg, s, {});
  EXPECT_FALSE(r.completed);
  EXPECT_NE(r.reason.find("less than min_step"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace velum
