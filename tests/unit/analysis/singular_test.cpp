// A singular Jacobian is reported with the DOFs that carry nothing and what to do about it:
// the classic case is a flat, unstressed membrane under pressure in a static analysis by plain
// Newton-Raphson. With the line search (the static default) its first correction borrows a
// small tension's stiffness (SecondOrderSystem::stiffen_stress_free) and it solves.
#include <gtest/gtest.h>

#include "square_membrane.hpp"  // bench/: the pressurised square shared with the benchmarks
#include "velum/analysis/analysis.hpp"

namespace velum {
namespace {

TEST(SingularJacobian, FlatMembraneUnderPressureNamesTheFreeNormalDofs) {
  auto model = pressurised_square(4);
  MechanicalSystem sys(*model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.time.t_end = 1, s.time.step = 0.5, s.time.min_step = 0.2;
  s.newton.line_search = false;
  const AnalysisResult res = run_analysis(sys, s);
  EXPECT_FALSE(res.loop.completed);
  const std::string& why = res.loop.reason;
  std::cout << "reason: " << why << "\n";
  EXPECT_NE(why.find("9 unconstrained DOF(s) with no stiffness"), std::string::npos);
  EXPECT_NE(why.find("node 7 z"), std::string::npos);  // the first interior node
  EXPECT_EQ(why.find("node 7 x"), std::string::npos);  // in-plane DOFs are stiff
  EXPECT_NE(why.find("dynamic analysis"), std::string::npos);
  EXPECT_NE(why.find("at t = 0"), std::string::npos);  // where it stopped
}

// The centre's deflection of the pressurised square solved statically from flat in `steps`
// load steps (a linear ramp).
double static_centre_deflection(int steps) {
  auto model = pressurised_square(4);
  TimeFunction ramp;
  ramp.kind = TimeFunction::Kind::kRamp;
  ramp.duration = 1.0;
  ramp.name = "ramp";
  model->functions.push_back(ramp);
  model->pressures[0].function = 0;
  MechanicalSystem sys(*model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.time.t_end = 1, s.time.step = 1.0 / steps;
  double w = 0;
  const AnalysisResult res = run_analysis(sys, s, [&](const StepSnapshot& snap) {
    w = snap.system.displacements(snap.step.t, snap.state.u)(2, 12);  // node 13: the centre
    return true;
  });
  EXPECT_TRUE(res.loop.completed) << res.loop.reason;
  return w;
}

TEST(SingularJacobian, TheSameMembraneSolvesStaticallyWithTheLineSearch) {
  const double one = static_centre_deflection(1), four = static_centre_deflection(4);
  EXPECT_GT(one, 0.01);  // lifted by the pressure, not a round-off dent
  // Two converged states, each within the Newton tolerance (measured: 3.8e-9 apart).
  EXPECT_NEAR(one, four, 2 * NewtonSettings{}.tolerance * one);
}

TEST(SingularJacobian, TheSameMembraneWithMassRunsDynamically) {
  auto model = pressurised_square(4);
  MechanicalSystem sys(*model);
  AnalysisSettings s;
  s.time.t_end = 0.01, s.time.step = 0.005;
  const AnalysisResult res = run_analysis(sys, s);
  EXPECT_TRUE(res.loop.completed) << res.loop.reason;
}

}  // namespace
}  // namespace velum
