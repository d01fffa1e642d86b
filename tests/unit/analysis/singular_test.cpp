// A singular Jacobian is reported with the DOFs that carry nothing and what to do about it:
// the classic case is a flat, unstressed membrane under pressure in a static analysis.
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
