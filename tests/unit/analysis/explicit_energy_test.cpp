// The energy account of explicit runs that no load drives (analysis.cpp, plausibility.hpp): a
// prestressed sheet thrown out of its plane, whose energy is the kinetic energy it starts
// with, and a prestressed sheet left at rest, which holds next to nothing. Neither may be
// reported as a blow-up ("energy created") or warned of, and the energies held must stay
// those the sheet started with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "unit_square.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

using test::explicit_run;

// A square of n x n quad4 (1 m, E t = 1 MN/m, ρ t = 1 kg/m²) clamped at its edges, prestressed
// to 1 kN/m both ways, with or without the tension field; no load. Its inner nodes start at
// `velocity` times sin πx sin πy (zero: at rest).
Model prestressed_square(int n, const Vec3& velocity, bool wrinkling) {
  Model m;
  test::UnitSquare sq = test::add_unit_square(m, n);
  LinearSheetLaw law(PlaneStressLaw::isotropic("film", 1e9, 0.3));
  law.with_prestress(Vec3(1e6, 1e6, 0));
  if (wrinkling) law.with_wrinkling();
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block("quad4", "sheet", std::move(sq.conn), m.X, law, 1000.0,
                                         1e-3, nullptr, shape::Integration::kGauss, report));
  m.fixed.push_back({sq.edge, {true, true, true}});
  // A smooth profile, sin πx sin πy times `velocity` (mostly the first mode: the central
  // difference's energy error is (ω h)² small there).
  if (velocity.squaredNorm() > 0)
    for (int node : sq.inner)
      m.initial_velocities.push_back({{node},
                                      velocity * std::sin(std::numbers::pi * m.X(0, node)) *
                                          std::sin(std::numbers::pi * m.X(1, node))});
  return m;
}

struct Outcome {
  AnalysisResult result;
  std::vector<std::string> warnings;
  double kinetic0 = 0;        ///< the kinetic energy at the start
  double largest_change = 0;  ///< of kinetic + strain from the start, over every step
  double largest_strain = 0;  ///< the strain energy's largest
};

Outcome run(const Model& m, int steps) {
  Outcome out;
  MechanicalSystem sys(m);
  const auto observe = [&](const StepSnapshot& snap) {
    const double strain = sys.strain_energy(snap.step.t, snap.state.u);
    const double held = sys.kinetic_energy(snap.state.v) + strain;
    out.largest_strain = std::max(out.largest_strain, strain);
    if (snap.step.step == 0) out.kinetic0 = held;
    out.largest_change = std::max(out.largest_change, std::abs(held - out.kinetic0));
    return snap.step.step < steps;
  };
  const auto warn = [&](const std::string& w) { out.warnings.push_back(w); };
  out.result = run_analysis(sys, explicit_run(1.0), observe, warn);
  return out;
}

TEST(ExplicitEnergy, ASheetThrownOutOfItsPlaneKeepsTheEnergyItStartedWith) {
  for (const bool wrinkling : {false, true}) {
    SCOPED_TRACE(wrinkling ? "tension field" : "elastic");
    const Outcome r = run(prestressed_square(8, Vec3(0, 0, 1), wrinkling), 600);
    EXPECT_EQ(r.result.loop.steps, 600) << r.result.loop.reason;
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    // ½ ∫ ρ t v² = 1/8 J for 1 m/s at the centre (ρ t = 1 kg/m²), lumped on 8 x 8 elements.
    ASSERT_GT(r.kinetic0, 0.1);
    ASSERT_LT(r.kinetic0, 0.15);
    EXPECT_EQ(r.result.energy.external_work, 0.0);
    // The energy moves between kinetic and strain (the sheet swings out of its plane) and
    // is kept to the central difference's own error (h² ω², a few percent at 0.9 of the
    // stable step): the account the run reports is the one the observer keeps.
    const Energies& E = r.result.energy;
    EXPECT_GT(r.largest_strain, 0.5 * r.kinetic0);
    EXPECT_NEAR(E.kinetic + E.strain, r.kinetic0, 0.1 * r.kinetic0);
    EXPECT_LT(r.largest_change, 0.1 * r.kinetic0);
  }
}

TEST(ExplicitEnergy, AnUnloadedPrestressedSheetAtRestStaysThere) {
  for (const bool wrinkling : {false, true}) {
    SCOPED_TRACE(wrinkling ? "tension field" : "elastic");
    const Outcome r = run(prestressed_square(8, Vec3::Zero(), wrinkling), 300);
    EXPECT_EQ(r.result.loop.steps, 300) << r.result.loop.reason;
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    // Only round-off moves it: the prestress's forces (1 kN/m over 1/8 m) balance to about
    // 1e-13 N, whose energy on the sheet's stiffness is far below a nanojoule.
    EXPECT_LT(r.largest_change, 1e-9);
    EXPECT_LT(std::abs(r.result.energy.kinetic + r.result.energy.strain), 1e-9);
  }
}

}  // namespace
}  // namespace velum
