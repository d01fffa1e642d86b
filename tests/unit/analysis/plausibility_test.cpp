// What makes a run implausible (docs/trust.md): non-finite values, deformation beyond ten
// model sizes (a rigid translation is not deformation), energy created by the solution.
#include <gtest/gtest.h>

#include "velum/analysis/analysis.hpp"
#include "velum/analysis/plausibility.hpp"

namespace velum {
namespace {

struct TwoNodes {
  Model model;
  State s;
  TwoNodes() {
    model.add_node(1, Vec3::Zero());
    model.add_node(2, Vec3(3, 4, 0));  // size 5
    s.u = s.v = s.a = VecX::Zero(6);
  }
};

TEST(Plausibility, DeformationBeyondTenModelSizesFails) {
  TwoNodes m;
  PlausibilityCheck check(m.model);
  EXPECT_DOUBLE_EQ(check.model_size(), 5);
  NodePositions U = NodePositions::Zero(3, 2);
  U(0, 1) = 95;  // 47.5 from the mean: 9.5 sizes
  EXPECT_EQ(check.check(0, U, m.s, false, 0, 0, 0), "");
  U(0, 1) = 105;  // 10.5 sizes
  const std::string why = check.check(0.5, U, m.s, false, 0, 0, 0);
  EXPECT_NE(why.find("implausible: at t = 0.5"), std::string::npos) << why;
  EXPECT_NE(why.find("10.5 times the model's size 5"), std::string::npos) << why;
  U.row(0).setConstant(1e6);  // a translation, however far, is no deformation
  EXPECT_EQ(check.check(0, U, m.s, false, 0, 0, 0), "");
}

TEST(Plausibility, NonFiniteValuesFail) {
  TwoNodes m;
  PlausibilityCheck check(m.model);
  m.s.v[3] = NAN;
  EXPECT_NE(check.check(1, NodePositions::Zero(3, 2), m.s, false, 0, 0, 0).find("non-finite"),
            std::string::npos);
}

TEST(Plausibility, EnergyCreatedFailsTheRunOrWarnsAtTheEnd) {
  TwoNodes m;
  PlausibilityCheck check(m.model);
  const NodePositions U = NodePositions::Zero(3, 2);
  // Held 0.9 of the work: dissipated, as generalized-α does; 1.75: its overshoot early on.
  EXPECT_EQ(check.check(1, U, m.s, true, 0.9, 1.0, 1.0), "");
  EXPECT_EQ(check.check(1, U, m.s, true, 1.75, 1.0, 1.0), "");
  // 12 times the work: a blow-up (the airbag: 3.5e12 of damping work against 4.9e5 of work).
  std::string why = check.check(2, U, m.s, true, 12, 1.0, 1.0);
  EXPECT_NE(why.find("the energy balance fails at t = 2"), std::string::npos) << why;
  why = check.check(4, U, m.s, true, 3.5e12, 4.9e5, 4.9e5);
  EXPECT_NE(why.find("the energy balance fails at t = 4"), std::string::npos) << why;
  // A step that does next to nothing from a stressed state: the changes are round-off of the
  // energy held at the start, not energy created (without it the floor is their own size).
  why = check.check(5, U, m.s, true, 2.342e-16, 2.082e-17, 2.082e-17);
  EXPECT_NE(why.find("the energy balance fails at t = 5"), std::string::npos) << why;
  EXPECT_EQ(check.check(5, U, m.s, true, 2.342e-16, 2.082e-17, 2.082e-17, 7.1e-3), "");
  EXPECT_NE(check.check(5, U, m.s, true, 1e-10, 2.082e-17, 2.082e-17, 7.1e-3), "");
  // Not checked when the run is not balanced (statics).
  EXPECT_EQ(check.check(4, U, m.s, false, 3.5e12, 4.9e5, 4.9e5), "");
  // At the end: 5% created is within the 10% allowed, 50% is a warning.
  std::vector<std::string> warnings;
  auto warn = [&](const std::string& w) { warnings.push_back(w); };
  EXPECT_EQ(check.final_balance(5, {.held = 1.05, .work = 1.0, .peak_work = 1.0}, warn), "");
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(check.final_balance(5, {.held = 1.5, .work = 1.0, .peak_work = 1.0}, warn), "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("50% of the work created"), std::string::npos) << warnings[0];
}

// The end-of-run balance is measured against the net work and the most work ever done, not
// the sum of the magnitudes of the work increments (an oscillating load grew that fortyfold,
// and 22% of the net work created passed as 0.5% of it).
TEST(Plausibility, EndBalanceAgainstNetWork) {
  TwoNodes m;
  const PlausibilityCheck check(m.model);
  std::vector<std::string> warnings;
  auto warn = [&](const std::string& w) { warnings.push_back(w); };
  // 22% of the net work created, the work having peaked at the net work.
  EXPECT_EQ(check.final_balance(9, {.held = 1.22, .work = 1.0, .peak_work = 1.0}, warn), "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("22% of the work created"), std::string::npos) << warnings[0];
  // A balanced run whose work oscillated: nothing to say.
  warnings.clear();
  EXPECT_EQ(check.final_balance(9, {.held = 1.001, .work = 1.0, .peak_work = 3.0}, warn), "");
  EXPECT_TRUE(warnings.empty());
  // Balanced at the end, but the energy held rose to three times all the work done (a folded
  // element whose energy spiked): a warning naming the time of the spike.
  EXPECT_EQ(check.final_balance(
                9, {.held = 1.0, .work = 1.0, .peak_work = 1.0, .peak_created = 2.0, .peak_t = 4.5},
                warn),
            "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("energy spike at t = 4.5"), std::string::npos) << warnings[0];
  // Past the documented factor (ten times all the work done created): the run fails.
  warnings.clear();
  const std::string why =
      check.final_balance(9, {.held = 12.5, .work = 1.0, .peak_work = 1.0}, warn);
  EXPECT_NE(why.find("the energy balance fails at the end"), std::string::npos) << why;
  EXPECT_TRUE(warnings.empty());
}

// The work of a prescribed motion is the reactions' (it was missing: a truss stretched by its
// end counted no work at all). Stretched 20% in 20 static steps, the trapezoidal work agrees
// with the strain energy ½ E A L ε², ε = (1.2² − 1)/2, to the rule's accuracy.
TEST(EnergyBalance, APrescribedMotionDoesWork) {
  Model m;
  m.add_node(1, Vec3::Zero());
  m.add_node(2, Vec3(0.5, 0, 0));  // free along x: an equation to solve
  m.add_node(3, Vec3::UnitX());
  BlockSetupReport report;
  m.blocks.push_back(make_cable_block("cable2", "bar", {0, 1, 1, 2}, m.X,
                                      CableLaw{.E = 100.0, .compression = true}, 1.0, 1.0,
                                      shape::Integration::kGauss, report));
  m.fixed.push_back({.nodes = {0}, .fix = {true, true, true}});
  m.fixed.push_back({.nodes = {1}, .fix = {false, true, true}});
  TimeFunction ramp;
  ramp.kind = TimeFunction::Kind::kRamp;
  m.functions.push_back(ramp);
  m.prescribed.push_back({.nodes = {2}, .displacement = Vec3(0.2, 0, 0), .function = 0});
  MechanicalSystem sys(m);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.time.t_end = 1, s.time.step = 0.05;
  const AnalysisResult res = run_analysis(sys, s);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  const double eps = (1.2 * 1.2 - 1) / 2, U = 0.5 * 100 * eps * eps;
  EXPECT_NEAR(res.energy.strain, U, 1e-12 * U);
  EXPECT_NEAR(res.energy.external_work, U, 2e-3 * U);
}

}  // namespace
}  // namespace velum
