// Path following through limit points against analytic load-displacement curves: a shallow
// two-bar truss snapping through (arc length, Crisfield's cylinder; displacement control) and
// a St Venant-Kirchhoff membrane strip compressed past its limit load (Riks).
#include <gtest/gtest.h>

#include <cmath>

#include "velum/analysis/analysis.hpp"

namespace velum {
namespace {

TimeFunction linear_in_t() {
  TimeFunction f;
  f.kind = TimeFunction::Kind::kTable;
  f.points = {{-1e3, -1e3}, {1e3, 1e3}};  // f(t) = t wherever the path goes
  return f;
}

// Two bars (E A = 1000, compression carried) from (∓1, 0, 0) to the apex (0, h, 0), h = 0.2;
// the apex moves along y under the downward force P = t. With y the apex height and L0 the
// bars' length, P(y) = E A y (h² − y²)/L0³: limit points at y = ±h/√3, the truss upside
// down at y = −h, and P rising again below.
struct ShallowTruss {
  static constexpr double kEA = 1000, kH = 0.2;
  Model model;
  ShallowTruss() {
    model.add_node(1, Vec3(-1, 0, 0));
    model.add_node(2, Vec3(1, 0, 0));
    model.add_node(3, Vec3(0, kH, 0));
    BlockSetupReport report;
    model.blocks.push_back(make_cable_block("cable2", "bars", {0, 2, 1, 2}, model.X,
                                            CableLaw{.E = kEA, .compression = true}, 1.0, 1.0,
                                            shape::Integration::kGauss, report));
    model.fixed.push_back({.nodes = {0, 1}, .fix = {true, true, true}});
    model.fixed.push_back({.nodes = {2}, .fix = {true, false, true}});
    model.functions.push_back(linear_in_t());
    model.point_loads.push_back({.nodes = {2}, .force = -Vec3::UnitY(), .function = 0});
  }
  static double L0() { return std::sqrt(1 + kH * kH); }
  static double load(double y) { return kEA * y * (kH * kH - y * y) / std::pow(L0(), 3); }
  static double limit_load() { return load(kH / std::sqrt(3.0)); }
};

struct PathPoint {
  double t, y;
  int negative_pivots;
};

std::vector<PathPoint> trace(ShallowTruss& truss, const AnalysisSettings& s, AnalysisResult& res) {
  MechanicalSystem sys(truss.model);
  std::vector<PathPoint> path;
  res = run_analysis(sys, s, [&](const StepSnapshot& snap) {
    const double y = ShallowTruss::kH + sys.displacements(snap.step.t, snap.state.u)(1, 2);
    path.push_back({snap.step.t, y, snap.step.report ? snap.step.report->negative_pivots : -1});
    return true;
  });
  return path;
}

// Checks a traced path against P(y): every point on the curve, both limit points passed
// (the load rises to the first, falls below the second's and rises again to t_end), the
// inertia one negative eigenvalue between them and none outside.
void expect_on_the_curve(const std::vector<PathPoint>& path, double t_end) {
  const double Pmax = ShallowTruss::limit_load(), yl = ShallowTruss::kH / std::sqrt(3.0);
  double t_max = -1e30, t_min = 1e30, y_min = 1e30;
  for (const auto& p : path) {
    EXPECT_NEAR(p.t, ShallowTruss::load(p.y), 1e-7 * Pmax) << "y = " << p.y;
    if (p.y >= 0) t_max = std::max(t_max, p.t);  // before the snap
    t_min = std::min(t_min, p.t);
    y_min = std::min(y_min, p.y);
    if (have_mumps() && p.negative_pivots >= 0 && std::abs(std::abs(p.y) - yl) > 1e-3) {
      EXPECT_EQ(p.negative_pivots, std::abs(p.y) < yl ? 1 : 0) << "y = " << p.y;
    }
  }
  EXPECT_GT(t_max, 0.97 * Pmax);
  EXPECT_LT(t_max, Pmax * (1 + 1e-9));
  EXPECT_LT(t_min, -0.97 * Pmax);
  EXPECT_LT(y_min, -ShallowTruss::kH);  // beyond the inverted position
  EXPECT_NEAR(path.back().t, t_end, 1e-9 * Pmax);
  // The far branch at t_end, by bisection on y < −h where P rises as y falls.
  double lo = -10 * ShallowTruss::kH, hi = -ShallowTruss::kH;
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (lo + hi);
    (ShallowTruss::load(m) > t_end ? lo : hi) = m;
  }
  EXPECT_NEAR(path.back().y, 0.5 * (lo + hi), 1e-8);
}

TEST(PathFollowing, ArcLengthTracesTheShallowTrussThroughBothLimitPoints) {
  ShallowTruss truss;
  const double t_end = 1.5 * ShallowTruss::limit_load();
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.path.method = PathSettings::Method::kArcLength;
  s.time.t_end = t_end, s.time.step = 0.1 * ShallowTruss::limit_load();
  AnalysisResult res;
  const auto path = trace(truss, s, res);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  std::cout << path.size() << " points, " << res.loop.iterations << " iterations\n";
  expect_on_the_curve(path, t_end);
}

TEST(PathFollowing, RiksTracesTheShallowTrussToo) {
  ShallowTruss truss;
  const double t_end = 1.5 * ShallowTruss::limit_load();
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.path.method = PathSettings::Method::kArcLength;
  s.path.constraint = PathSettings::Constraint::kRiks;
  s.path.arc_length = 0.02;
  s.time.t_end = t_end, s.time.step = 0.1 * ShallowTruss::limit_load();
  AnalysisResult res;
  const auto path = trace(truss, s, res);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  expect_on_the_curve(path, t_end);
}

TEST(PathFollowing, DisplacementControlDrivesTheApexThroughTheSnap) {
  ShallowTruss truss;
  const double d = -2.5 * ShallowTruss::kH;
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.path.method = PathSettings::Method::kDisplacement;
  s.path.node = 2, s.path.component = 1, s.path.displacement = d;
  s.time.t_end = 1, s.time.step = 0.02;
  AnalysisResult res;
  const auto path = trace(truss, s, res);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  EXPECT_EQ(path.size(), 51u);  // the start and 50 steps
  expect_on_the_curve(path, ShallowTruss::load(ShallowTruss::kH + d));
  EXPECT_NEAR(path.back().y, ShallowTruss::kH + d, 1e-12);
}

// A strip of 4 x 1 quad4 (E = 1000, ν = 0, thickness 1) held at x = 0 and compressed by an
// edge load t per unit length at x = 4, in its plane: a uniform stretch λ with
// −t = E λ (λ² − 1)/2, the limit load E/(3√3) at λ = 1/√3. Riks follows it past the limit
// and down to λ = 0.35, and so does Crisfield's cylinder.
class MembraneStrip : public testing::TestWithParam<PathSettings::Constraint> {};

TEST_P(MembraneStrip, ArcLengthFollowsItPastItsLimitLoad) {
  constexpr double kE = 1000, kL = 4;
  Model m;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 4; ++i) m.add_node(10 * j + i + 1, Vec3(i, j, 0));
  std::vector<int> conn;
  for (int i = 0; i < 4; ++i) conn.insert(conn.end(), {i, i + 1, i + 6, i + 5});
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block("quad4", "strip", conn, m.X,
                                         PlaneStressLaw::isotropic("iso", kE, 0.0), 1.0, 1.0,
                                         nullptr, shape::Integration::kGauss, report));
  m.fixed.push_back({.nodes = {0, 5}, .fix = {true, false, true}});
  m.fixed.push_back({.nodes = {0}, .fix = {true, true, true}});
  m.fixed.push_back({.nodes = {1, 2, 3, 4, 6, 7, 8, 9}, .fix = {false, false, true}});
  m.functions.push_back(linear_in_t());
  m.edge_loads.push_back({.nodes = {4, 9}, .force_per_length = -Vec3::UnitX(), .function = 0});
  MechanicalSystem sys(m);
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kStatic;
  s.path.method = PathSettings::Method::kArcLength;
  s.path.constraint = GetParam();
  s.time.t_end = 1e3, s.time.step = 10;
  double t_max = 0, lambda_min = 1;
  int points = 0;
  const AnalysisResult res = run_analysis(sys, s, [&](const StepSnapshot& snap) {
    const NodePositions U = sys.displacements(snap.step.t, snap.state.u);
    const double lambda = 1 + U(0, 4) / kL;
    for (int n = 0; n < m.num_nodes(); ++n) {  // uniform: u = (λ − 1) x, no lateral motion
      EXPECT_NEAR(U(0, n), (lambda - 1) * m.X(0, n), 1e-9);
      EXPECT_NEAR(U(1, n), 0, 1e-9);
    }
    EXPECT_NEAR(-snap.step.t, kE * lambda * (lambda * lambda - 1) / 2, 1e-7 * kE);
    t_max = std::max(t_max, snap.step.t);
    lambda_min = std::min(lambda_min, lambda);
    ++points;
    return lambda > 0.35;
  });
  EXPECT_TRUE(res.loop.stopped) << res.loop.reason;
  EXPECT_GT(t_max, 0.97 * kE / (3 * std::sqrt(3.0)));
  EXPECT_LE(t_max, kE / (3 * std::sqrt(3.0)) * (1 + 1e-9));
  EXPECT_LT(lambda_min, 0.36);
  std::cout << points << " points\n";
}

INSTANTIATE_TEST_SUITE_P(PathFollowing, MembraneStrip,
                         testing::Values(PathSettings::Constraint::kRiks,
                                         PathSettings::Constraint::kCylindrical));

}  // namespace
}  // namespace velum
