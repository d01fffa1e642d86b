// The one entry point for every analysis type (analysis/analysis.hpp): it runs form finding as
// run_form_finding does, refuses form finding where no model is given to move, names every
// type from one table, and resolves the displacement control's equation in one place.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "velum/analysis/form_finding.hpp"

namespace velum {
namespace {

// Five nodes of a sagging cable between two pinned ends, prestressed: form finding pulls it
// straight.
Model sagging_cable() {
  Model m;
  for (int i = 0; i < 5; ++i) m.add_node(i + 1, Vec3(i, 0, i == 0 || i == 4 ? 0.0 : -0.1));
  BlockSetupReport report;
  CableLaw law;
  law.E = 1.0;
  law.S0 = 10.0;
  m.blocks.push_back(make_cable_block("cable2", "cable", {0, 1, 1, 2, 2, 3, 3, 4}, m.X, law, 1.0,
                                      1.0, shape::Integration::kGauss, report));
  FixedDofs ends;
  ends.fix = {true, true, true};
  ends.nodes = {0, 4};
  m.fixed.push_back(ends);
  return m;
}

AnalysisSettings form_finding() {
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kFormFinding;
  s.time.t_end = 1, s.time.step = 1;
  s.form_finding.max_updates = 50;
  return s;
}

TEST(RunAnalysis, FormFindingThroughTheEntryPointIsRunFormFinding) {
  Model a = sagging_cable(), b = sagging_cable();
  MechanicalSystem sys_a(a), sys_b(b);
  FormFindingReport direct, entry;
  int steps = 0;
  const AnalysisResult r_direct = run_form_finding(a, sys_a, form_finding(), {}, {}, &direct);
  const AnalysisResult r_entry = run_analysis(
      b, sys_b, form_finding(),
      {.step = [&](const StepSnapshot&) { return ++steps > 0; }, .warning = {}, .form = &entry});
  ASSERT_TRUE(r_entry.loop.completed) << r_entry.loop.reason;
  EXPECT_EQ(r_entry.loop.completed, r_direct.loop.completed);
  EXPECT_EQ(entry.updates, direct.updates);
  EXPECT_EQ(entry.residual, direct.residual);
  EXPECT_EQ(entry.shape, direct.shape);
  EXPECT_GT(steps, 0);
  EXPECT_LT(entry.shape.row(2).cwiseAbs().maxCoeff(), 1e-6);  // pulled straight
}

TEST(RunAnalysis, FormFindingNeedsTheModelItMoves) {
  Model m = sagging_cable();
  MechanicalSystem sys(m);
  EXPECT_THROW(run_analysis(sys, form_finding()), std::invalid_argument);
}

TEST(RunAnalysis, EveryTypeHasOneNameMethodAndRun) {
  std::set<std::string> names;
  for (const AnalysisTypeInfo& i : kAnalysisTypes) {
    AnalysisSettings s;
    s.type = i.type;
    EXPECT_EQ(s.type_name(), i.name);
    EXPECT_FALSE(s.method().empty());
    EXPECT_FALSE(s.run_name().empty());
    names.insert(i.name);
  }
  EXPECT_EQ(names.size(), std::size(kAnalysisTypes));
  AnalysisSettings dynamic;
  dynamic.type = AnalysisSettings::Type::kDynamic;
  dynamic.scheme = "newmark";
  EXPECT_EQ(dynamic.method(), "newmark");
  EXPECT_EQ(dynamic.run_name(), "dynamic run (newmark)");
}

TEST(RunAnalysis, PathEquationResolvedOnceAndRefusedWhenFixed) {
  const Model m = sagging_cable();
  const DofMap dofs(m);
  PathSettings free;
  free.method = PathSettings::Method::kDisplacement;
  free.node = 2, free.component = 2;
  EXPECT_EQ(resolve_path_equation(free, m, dofs), "");
  EXPECT_EQ(free.equation, dofs.global_equation(2, 2));
  EXPECT_GE(free.equation, 0);
  free.equation = 1;  // already resolved (under mpirun, on the whole model): left alone
  EXPECT_EQ(resolve_path_equation(free, m, dofs), "");
  EXPECT_EQ(free.equation, 1);
  PathSettings fixed = free;
  fixed.equation = -1, fixed.node = 4;
  EXPECT_EQ(resolve_path_equation(fixed, m, dofs),
            "analysis.path: node 5 z is fixed, prescribed or normal to a symmetry plane: "
            "displacement control needs a free component");
}

}  // namespace
}  // namespace velum
