// A prestressed flat sheet under a follower pressure solves as `static` from the flat state
// (issue 16: "no stiffness ... add prestress"), with and without wrinkling, and deflects as
// the tensioned membrane of the linear theory, N ∇²w = −p on the square held at its edges:
// w(centre) = 16 p a² / (π⁴ N) Σ_{m,n odd} (−1)^((m+n)/2−1) / (m n (m² + n²)) = 0.0737 p a²/N.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "velum/analysis/analysis.hpp"

namespace velum {
namespace {

TEST(PrestressedSheet, FlatSheetUnderFollowerPressureSolvesStatic) {
  const double pi = std::acos(-1.0);
  const double a = 1, t = 1e-3, sigma0 = 1e3, N = sigma0 * t, E = 1e5;
  const int n = 16;
  double series = 0;
  for (int m = 1; m < 400; m += 2)
    for (int k = 1; k < 400; k += 2)
      series += ((((m + k) / 2 - 1) % 2) ? -1.0 : 1.0) /
                (double(m) * k * (double(m) * m + double(k) * k));
  const double w_per_p = 16 * a * a / (std::pow(pi, 4) * N) * series;
  const double p = 0.002 * a / w_per_p;  // centre deflection a / 500: the linear range
  for (const bool wrinkling : {false, true}) {
    Model m;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.add_node(1 + j * (n + 1) + i, Vec3(a * i / n, a * j / n, 0));
    std::vector<int> conn;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int k : {j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
                      (j + 1) * (n + 1) + i})
          conn.push_back(k);
    SheetLaw law = SheetLaw(PlaneStressLaw::isotropic("sheet", E, 0.3))
                       .with_prestress(Vec3(sigma0, sigma0, 0));
    if (wrinkling) law.with_wrinkling();
    BlockSetupReport report;
    m.blocks.push_back(make_membrane_block("quad4", "sheet", conn, m.X, law, 1.0, t, nullptr,
                                           shape::Integration::kGauss, report));
    FixedDofs edges;
    edges.fix = {true, true, true};
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || i == n || j == n) edges.nodes.push_back(j * (n + 1) + i);
    m.fixed.push_back(edges);
    TimeFunction ramp;
    ramp.kind = TimeFunction::Kind::kRamp;
    m.functions.push_back(ramp);
    PressureLoad pl;
    pl.block = 0, pl.value = p, pl.function = 0;
    for (int e = 0; e < n * n; ++e) pl.elements.push_back(e);
    m.pressures.push_back(pl);
    MechanicalSystem sys(m);
    AnalysisSettings s;
    s.type = AnalysisSettings::Type::kStatic;
    s.time.t_end = 1, s.time.step = 0.25;
    double w = 0;
    const AnalysisResult res = run_analysis(sys, s, [&](const StepSnapshot& snap) {
      w = sys.displacements(snap.step.t, snap.state.u)(2, n / 2 * (n + 1) + n / 2);
      return true;
    });
    ASSERT_TRUE(res.loop.completed) << res.loop.reason;
    std::cout << (wrinkling ? "wrinkling" : "elastic") << " prestressed sheet: centre " << w
              << ", linear theory " << p * w_per_p << "\n";
    EXPECT_NEAR(w, p * w_per_p, 0.02 * p * w_per_p);
  }
}

}  // namespace
}  // namespace velum
