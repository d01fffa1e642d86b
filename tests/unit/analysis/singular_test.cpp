// A singular Jacobian is reported with the DOFs that carry nothing and what to do about it:
// the classic case is a flat, unstressed membrane under pressure in a static analysis.
#include <gtest/gtest.h>

#include "velum/analysis/analysis.hpp"

namespace velum {
namespace {

std::unique_ptr<Model> flat_square(int n) {
  auto m = std::make_unique<Model>();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m->add_node(100 + j * (n + 1) + i, Vec3(double(i) / n, double(j) / n, 0));
  std::vector<int> conn, edge;
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      conn.insert(conn.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (i == 0 || j == 0 || i == n || j == n) edge.push_back(id(i, j));
  BlockSetupReport report;
  m->blocks.push_back(make_membrane_block("quad4", "sheet", std::move(conn), m->X,
                                          PlaneStressLaw::isotropic("film", 1e6, 0.3), 1.0, 1e-3,
                                          nullptr, report));
  m->fixed.push_back({edge, {true, true, true}});
  PressureLoad p;
  p.block = 0;
  p.value = 10;
  for (int e = 0; e < m->blocks[0]->size(); ++e) p.elements.push_back(e);
  m->pressures.push_back(std::move(p));
  return m;
}

TEST(SingularJacobian, FlatMembraneUnderPressureNamesTheFreeNormalDofs) {
  auto model = flat_square(4);
  MechanicalSystem sys(*model);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.time.t_end = 1, s.time.step = 0.5, s.time.min_step = 0.2;
  const AnalysisResult res = run_analysis(sys, s);
  EXPECT_FALSE(res.loop.completed);
  const std::string& why = res.loop.reason;
  std::cout << "reason: " << why << "\n";
  EXPECT_NE(why.find("9 unconstrained DOF(s) with no stiffness"), std::string::npos);
  EXPECT_NE(why.find("node 106 z"), std::string::npos);  // the first interior node
  EXPECT_EQ(why.find("node 106 x"), std::string::npos);  // in-plane DOFs are stiff
  EXPECT_NE(why.find("dynamic analysis"), std::string::npos);
  EXPECT_NE(why.find("at t = 0"), std::string::npos);  // where it stopped
}

TEST(SingularJacobian, TheSameMembraneWithMassRunsDynamically) {
  auto model = flat_square(4);
  MechanicalSystem sys(*model);
  AnalysisSettings s;
  s.time.t_end = 0.01, s.time.step = 0.005;
  const AnalysisResult res = run_analysis(sys, s);
  EXPECT_TRUE(res.loop.completed) << res.loop.reason;
}

}  // namespace
}  // namespace velum
