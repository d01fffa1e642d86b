// Limit points and stability in static load stepping: a St Venant-Kirchhoff truss loaded in
// compression to near its limit point and back into tension stays on the stable branch, a
// state that turns an element inside out is never accepted, and the inertia of each
// equilibrium is reported.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "velum/analysis/analysis.hpp"

namespace velum {
namespace {

// One bar from (0, 0, 0) to (1, 0, 0), E A = 1, compression carried (a truss), the far end
// free along x under the force P(t) = table(t). Its nominal force is P = λ (λ² − 1)/2 for the
// stretch λ: a limit point at λ = 1/√3, P = −1/(3√3).
struct Truss {
  Model model;
  explicit Truss(std::vector<std::pair<double, double>> table) {
    model.add_node(1, Vec3::Zero());
    model.add_node(2, Vec3::UnitX());
    BlockSetupReport report;
    model.blocks.push_back(make_cable_block("cable2", "bar", {0, 1}, model.X,
                                            CableLaw{.E = 1.0, .compression = true}, 1.0, 1.0,
                                            shape::Integration::kGauss, report));
    model.fixed.push_back({.nodes = {0}, .fix = {true, true, true}});
    model.fixed.push_back({.nodes = {1}, .fix = {false, true, true}});
    TimeFunction f;
    f.kind = TimeFunction::Kind::kTable;
    f.points = std::move(table);
    model.functions.push_back(f);
    model.point_loads.push_back({.nodes = {1}, .force = Vec3::UnitX(), .function = 0});
  }
};

// The roots of λ³ − λ − 2P = 0 (Cardano, trigonometric form, three real roots for
// |P| < 1/(3√3)): k = 0 is the stable branch λ > 1/√3.
double stretch_root(double P, int k) {
  const double c = std::acos(3 * std::sqrt(3.0) * P) / 3;
  return 2 / std::sqrt(3.0) * std::cos(c - 2 * std::numbers::pi * k / 3);
}

struct TrussRun {
  AnalysisResult result;
  std::vector<double> t, stretch;
  std::vector<int> negative_pivots;
};

TrussRun run_truss(Truss& truss, double step, AnalysisSettings::Predictor predictor,
                   SolverKind solver = SolverKind::kAuto) {
  MechanicalSystem sys(truss.model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.predictor = predictor;
  s.solver = solver;
  s.time.t_end = 3, s.time.step = step, s.time.output_interval = step;
  TrussRun run;
  run.result = run_analysis(sys, s, [&](const StepSnapshot& snap) {
    run.t.push_back(snap.step.t);
    run.stretch.push_back(1 + sys.displacements(snap.step.t, snap.state.u)(0, 1));
    run.negative_pivots.push_back(snap.step.report ? snap.step.report->negative_pivots : -1);
    return true;
  });
  return run;
}

double stretch_at(const TrussRun& run, double t) {
  for (size_t i = 0; i < run.t.size(); ++i)
    if (std::abs(run.t[i] - t) < 1e-9) return run.stretch[i];
  ADD_FAILURE() << "no output at t = " << t;
  return NAN;
}

// The references of the reversal: compression to P = −0.19 (98.7 % of the limit load), back
// to −0.058 and on into tension, +0.074. The unstable roots the extrapolating predictor used
// to converge on are 0.1176 and −0.1515 (an inverted bar), and main said "converged".
TEST(LimitPoint, TrussReversalStaysOnTheStableBranch) {
  const double P1 = -0.19, P2 = -0.058, P3 = 0.074;
  ASSERT_LT(-P1, 1 / (3 * std::sqrt(3.0)));
  for (double step : {1.0, 0.5, 0.25, 0.1}) {
    for (auto predictor :
         {AnalysisSettings::Predictor::kExtrapolate, AnalysisSettings::Predictor::kNone}) {
      SCOPED_TRACE(testing::Message() << "step " << step << " predictor "
                                      << (predictor == AnalysisSettings::Predictor::kNone));
      Truss truss({{0, 0}, {1, P1}, {2, P2}, {3, P3}});
      const TrussRun run = run_truss(truss, step, predictor);
      ASSERT_TRUE(run.result.loop.completed) << run.result.loop.reason;
      EXPECT_NEAR(stretch_at(run, 1), stretch_root(P1, 0), 1e-6);
      EXPECT_NEAR(stretch_at(run, 2), stretch_root(P2, 0), 1e-6);
      EXPECT_NEAR(stretch_at(run, 3), stretch_root(P3, 0), 1e-6);
      EXPECT_NEAR(stretch_at(run, 2), 0.935984, 1e-6);  // the figures
      EXPECT_NEAR(stretch_at(run, 3), 1.067096, 1e-6);
      // Every equilibrium on the path is stable, and the factorisation said so.
      for (size_t i = 1; i < run.negative_pivots.size(); ++i)
        EXPECT_EQ(run.negative_pivots[i], have_mumps() ? 0 : run.negative_pivots[i]) << i;
      EXPECT_TRUE(run.result.warnings.empty());
    }
  }
}

// Past the limit load under load control there is no nearby equilibrium: the run fails (it
// never converges on the bar turned inside out, λ < 0, which is the only root left).
TEST(LimitPoint, PastTheLimitLoadTheInvertedBarIsNeverAccepted) {
  Truss truss({{0, 0}, {1, -0.25}});
  MechanicalSystem sys(truss.model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.time.t_end = 1, s.time.step = 0.1, s.time.min_step = 1e-4;
  double last = 1;
  const AnalysisResult res = run_analysis(sys, s, [&](const StepSnapshot& snap) {
    last = 1 + sys.displacements(snap.step.t, snap.state.u)(0, 1);
    return true;
  });
  EXPECT_FALSE(res.loop.completed);
  EXPECT_GT(last, 0);                                             // never through zero length
  EXPECT_LT(res.loop.t, 1 / (3 * std::sqrt(3.0)) / 0.25 + 1e-3);  // stopped at the limit load
}

// A state on the unstable branch is reported: the truss started there (the unstable root at
// P = −0.1) and held at that load, with the predictor off so nothing moves it away.
TEST(LimitPoint, AnUnstableEquilibriumIsReportedWithAWarning) {
  if (!have_mumps()) GTEST_SKIP() << "the inertia needs MUMPS's LDLᵀ";
  const double P = -0.1;
  Truss truss({{0, P}, {1, P}});
  MechanicalSystem sys(truss.model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.predictor = AnalysisSettings::Predictor::kNone;
  s.time.t_end = 1, s.time.step = 0.5;
  std::vector<std::string> seen;
  std::vector<int> neg;
  State start;
  start.u = start.v = start.a = VecX::Zero(sys.size());
  start.u[0] = stretch_root(P, 1) - 1;  // the unstable root
  const AnalysisResult res = run_analysis(
      sys, s,
      [&](const StepSnapshot& snap) {
        if (snap.step.report) neg.push_back(snap.step.report->negative_pivots);
        return true;
      },
      [&](const std::string& w) { seen.push_back(w); }, &start);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  ASSERT_EQ(neg.size(), 2u);
  EXPECT_EQ(neg[0], 1);
  EXPECT_EQ(neg[1], 1);
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_EQ(seen, res.warnings);
  EXPECT_NE(res.warnings[0].find("unstable equilibrium from t = 0.5"), std::string::npos)
      << res.warnings[0];
}

}  // namespace
}  // namespace velum
