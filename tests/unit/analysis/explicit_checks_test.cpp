// The trust checks of explicit runs, amortised (analysis.hpp, kExplicitCheckInterval): an
// element turned inside out and a blow-up are still reported, at most that many steps late;
// the work of the loads is booked every step, and the energies held are those of the last
// state at the end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "unit_square.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/analysis/plausibility.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

using test::explicit_run;
using test::pressurised_square;

// One tri3 (E t = 1 N/m, ρ t = 1 kg/m²: a wave speed of 1 m/s) with nodes 1 and 2 fixed and
// node 3 free in its plane, thrown at `velocity`.
Model thrown_triangle(const Vec3& velocity) {
  Model m;
  m.add_node(1, Vec3(0, 0, 0));
  m.add_node(2, Vec3(1, 0, 0));
  m.add_node(3, Vec3(0.5, 1, 0));
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block("tri3", "sheet", {0, 1, 2}, m.X,
                                         PlaneStressLaw::isotropic("film", 1e3, 0.3), 1000.0, 1e-3,
                                         nullptr, shape::Integration::kGauss, report));
  m.fixed.push_back({{0, 1}, {true, true, true}});
  m.fixed.push_back({{2}, {false, false, true}});
  m.initial_velocities.push_back({{2}, velocity});
  return m;
}

TEST(ExplicitChecks, AnElementTurnedInsideOutIsReportedWithinTheInterval) {
  // Node 3, pulled by 1 N towards the edge 1-2 (about five times the most the flattening
  // triangle resists), goes through it towards the mirror image after about 600 steps of
  // 1 ms: the inversion falls between checks, and the run goes on past it.
  Model m = thrown_triangle(Vec3::Zero());
  m.point_loads.push_back({{2}, Vec3(0, -1, 0), -1});
  MechanicalSystem sys(m);
  int step = 0, inverted_at = 0, warned_at = 0;
  const auto observe = [&](const StepSnapshot& snap) {
    step = snap.step.step;
    const double y = m.X(1, 2) + sys.displacements(snap.step.t, snap.state.u)(1, 2);
    if (y < 0 && inverted_at == 0) inverted_at = step;
    return true;
  };
  const auto warn = [&](const std::string& w) {
    // The check runs before the observer sees the step.
    if (w.find("turns inside out") != std::string::npos && warned_at == 0) warned_at = step + 1;
  };
  const AnalysisResult r = run_analysis(sys, explicit_run(1.0, 1e-3), observe, warn);
  ASSERT_TRUE(r.loop.completed) << r.loop.reason;
  ASSERT_GT(inverted_at, 3 * kExplicitCheckInterval);             // not the first check's
  ASSERT_LT(inverted_at + kExplicitCheckInterval, r.loop.steps);  // not the end's
  EXPECT_NE(inverted_at % kExplicitCheckInterval, 0);             // between checks
  EXPECT_GT(warned_at, 0);
  EXPECT_GE(warned_at, inverted_at);
  EXPECT_LE(warned_at, inverted_at + kExplicitCheckInterval);
}

TEST(ExplicitChecks, ABlowUpFailsTheRunWithinTheInterval) {
  // The square without prestress under a pressure that stretches it until the step, 0.9 of
  // the stable one at the start and kept, is unstable (after about 2,800 steps): the oscillation
  // grows from round-off, faster as it stiffens the sheet. The observer keeps its own account
  // every step (as the check does, PlausibilityLimits): the run fails at most one interval
  // after the energy created first exceeds ten times the work or a node is ten sizes from
  // the mean. A blow-up that races from there to a non-finite acceleration within the
  // interval is failed by the step itself (a heavier pressure does so).
  Model m = pressurised_square(5e4, 0);
  const double size = PlausibilityCheck(m).model_size();
  MechanicalSystem sys(m);
  const VecX zero = VecX::Zero(sys.size());
  NodePositions U_prev = NodePositions::Zero(3, m.num_nodes());
  NodePositions F_prev = sys.external_forces(0, zero, zero);
  double work = 0, work_scale = 0;
  int step = 0, bad_at = 0;
  const auto observe = [&](const StepSnapshot& snap) {
    step = snap.step.step;
    const NodePositions U = sys.displacements(snap.step.t, snap.state.u);
    const NodePositions F = sys.external_forces(snap.step.t, snap.state.u, snap.state.v);
    const double dW = 0.5 * ((F + F_prev).array() * (U - U_prev).array()).sum();
    work += dW, work_scale += std::abs(dW);
    U_prev = U, F_prev = F;
    const double held =
        sys.kinetic_energy(snap.state.v) + sys.strain_energy(snap.step.t, snap.state.u);
    const Vec3 mean = U.rowwise().mean();
    const bool far = (U.colwise() - mean).colwise().norm().maxCoeff() > 10 * size;
    if (bad_at == 0 && (held - work > 10 * work_scale || far)) bad_at = step;
    return true;
  };
  // The step fixed at the start (stable_step: start): what is tested is the checks. (With
  // the step estimated again at every check this run blows up as well: the sheet, struck at
  // once, swings through flat and compressed states whose stiffness changes by more than
  // the safety factor's margin within one interval: measured, the dense critical step fell
  // from 2.64e-4 to 2.03e-4 within 20 steps of the check that set 2.41e-4, the tangent
  // indefinite in between. ExplicitStep.AStiffeningSheetBlowsUpOnTheStartStepAndHoldsOnThe
  // CurrentOne tests the re-estimated step on a ramped pressure.)
  AnalysisSettings settings = explicit_run(1.0);
  settings.explicit_step.from_current_state = false;
  settings.explicit_step.safety = 0.9;  // the old default: at 0.6 this strike is survived
  const AnalysisResult r = run_analysis(sys, settings, observe);
  EXPECT_FALSE(r.loop.completed);
  EXPECT_TRUE(r.loop.reason.find("implausible") != std::string::npos ||
              r.loop.reason.find("non-finite") != std::string::npos)
      << r.loop.reason;
  ASSERT_GT(bad_at, 3 * kExplicitCheckInterval);  // not the first check's
  EXPECT_GE(step + 1, bad_at);                    // the failing step is not observed
  EXPECT_LE(step + 1, bad_at + kExplicitCheckInterval);
}

TEST(ExplicitChecks, TheWorkIsBookedEveryStepAndTheEnergiesHeldAtTheEnd) {
  // A pressurised square of 4 x 4 quad4 clamped at its edges, from rest, over a number of
  // steps that is no multiple of the interval: the work against one booked independently
  // every step, the energies held against those of the last state.
  Model m = pressurised_square(100, 1e6);
  MechanicalSystem sys(m);
  ASSERT_TRUE(sys.external_forces_reusable());

  const int steps = 3 * kExplicitCheckInterval + 7;
  double work = 0, t_end = 0;
  const VecX zero = VecX::Zero(sys.size());
  NodePositions U_prev = NodePositions::Zero(3, m.num_nodes());
  NodePositions F_prev = sys.external_forces(0, zero, zero);
  State last;
  const auto observe = [&](const StepSnapshot& snap) {
    const NodePositions U = sys.displacements(snap.step.t, snap.state.u);
    const NodePositions F = sys.external_forces(snap.step.t, snap.state.u, snap.state.v);
    work += 0.5 * ((F + F_prev).array() * (U - U_prev).array()).sum();
    U_prev = U, F_prev = F;
    last = snap.state;
    t_end = snap.step.t;
    return snap.step.step < steps;
  };
  const AnalysisResult r = run_analysis(sys, explicit_run(1.0), observe);
  ASSERT_EQ(r.loop.steps, steps);
  ASSERT_GT(work, 0);
  EXPECT_NEAR(r.energy.external_work, work, 1e-12 * work);
  EXPECT_NEAR(r.energy.kinetic, sys.kinetic_energy(last.v), 1e-12 * r.energy.kinetic);
  const double strain = sys.strain_energy(t_end, last.u);
  EXPECT_NEAR(r.energy.strain, strain, 1e-12 * std::abs(strain));
}

}  // namespace
}  // namespace velum
