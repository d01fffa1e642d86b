// The stress map's unloading branch (StressMapData::unloading): a load-unload-reload cycle in
// the warp direction against its closed form (the map on loading, the straight line of the
// unloading modulus from the largest strain below it, the map again beyond), the history only
// moving on at accepted states, the tangent against central differences on unloading states
// (anisotropic, and wrinkled through the section's wrapper), and moduli softer than the map
// refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "fabric_response.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/material/stress_map_sheet_law.hpp"

namespace velum {
namespace {

using fabric_response::s11;
using fabric_response::s22;

constexpr double kWarp = 2000, kFill = 1500;

StressMapData fabric(double warp = kWarp, double fill = kFill) {
  StressMapData d;
  d.e1 = {-0.02, 0, 0.01, 0.025, 0.04, 0.06};
  d.e2 = {-0.02, 0, 0.015, 0.03, 0.05};
  for (double e2 : d.e2)
    for (double e1 : d.e1) d.S11.push_back(s11(e1, e2)), d.S22.push_back(s22(e1, e2));
  d.G12 = 30;
  d.unloading[0] = warp;
  d.unloading[1] = fill;
  return d;
}

Mat3 central_differences(const SheetLawBase& law, const Vec3& E, std::span<const double> h) {
  Mat3 C;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += 1e-8;
    Em[j] -= 1e-8;
    SheetResponse rp, rm;
    law.evaluate(Ep, h, rp);
    law.evaluate(Em, h, rm);
    C.col(j) = (rp.S - rm.S) / 2e-8;
  }
  return C;
}

TEST(StressMapUnloading, LoadUnloadReloadCycleMatchesTheClosedForm) {
  const StressMapSheetLaw law("pvc", fabric());
  ASSERT_EQ(law.state_size(), 2);
  double h[2] = {1, 1};
  law.initial_state(h);
  EXPECT_EQ(h[0], 0.0);
  // Warp strain 0 -> 0.04 -> -0.01 -> 0.05 in accepted steps, the fill strain held at 0.015
  // (a grid line, so the map's values there are the table's where the path meets grid points).
  const double e2 = 0.015, peak = 0.04;
  const double turn = s11(peak, e2);  // a table point: the map gives it exactly
  double worst = 0, worst_fill = 0;
  auto expect = [&](double e, double emax) {
    SheetResponse r, m;
    law.evaluate(Vec3(e, e2, 0), h, r);
    law.evaluate(Vec3(e, e2, 0), m);  // the map alone
    const double closed = e >= emax ? m.S[0] : turn - kWarp * (emax - e);
    worst = std::max(worst, std::abs(r.S[0] - closed));
    worst_fill = std::max(worst_fill, std::abs(r.S[1] - m.S[1]));  // fill: loading (e2 = max)
  };
  std::vector<double> path;
  for (int k = 0; k <= 40; ++k) path.push_back(peak * k / 40);          // loading
  for (int k = 1; k <= 50; ++k) path.push_back(peak - 0.05 * k / 50);   // unloading
  for (int k = 1; k <= 60; ++k) path.push_back(-0.01 + 0.06 * k / 60);  // reloading past
  double emax = 0;
  for (double e : path) {
    expect(e, emax);
    law.update_state(Vec3(e, e2, 0), h);
    emax = std::max(emax, e);
    EXPECT_DOUBLE_EQ(h[0], emax);
  }
  std::printf(
      "[stress map unloading] cycle: max |S11 - closed form| = %.2e (turning stress "
      "%.4g), fill %.2e\n",
      worst, turn, worst_fill);
  EXPECT_LT(worst, 1e-9 * turn);
  EXPECT_EQ(worst_fill, 0.0);
  // The strain left at zero warp stress after unloading from the peak: the line's root.
  const double residual = peak - turn / kWarp;
  double g[2] = {peak, e2};
  SheetResponse r;
  law.evaluate(Vec3(residual, e2, 0), g, r);
  EXPECT_NEAR(r.S[0], 0.0, 1e-12 * turn);
  EXPECT_GT(residual, 0.0);
}

TEST(StressMapUnloading, TangentMatchesCentralDifferencesOnUnloadingStates) {
  const StressMapSheetLaw law("pvc", fabric());
  const double h[2] = {0.045, 0.035};
  double worst = 0;
  // Both directions unloading, one, none; inside and beyond the grid; with shear.
  for (const Vec3& E : {Vec3(0.02, 0.01, 0.01), Vec3(0.044, -0.01, -0.03), Vec3(0.05, 0.02, 0.0),
                        Vec3(-0.03, 0.03, 0.02), Vec3(0.07, 0.06, 0.01)}) {
    SheetResponse r;
    law.evaluate(E, h, r);
    const Mat3 fd = central_differences(law, E, h);
    worst = std::max(worst, (r.C - fd).cwiseAbs().maxCoeff() / r.C.cwiseAbs().maxCoeff());
  }
  std::printf("[stress map unloading] tangent against central differences: %.2e\n", worst);
  EXPECT_LT(worst, 1e-6);

  // Wrinkled: stretched along 0.5 rad, shortened across, after a larger stretch was reached.
  const SheetLaw wrinkled = SheetLaw(StressMapSheetLaw("pvc", fabric())).with_wrinkling(0);
  ASSERT_EQ(wrinkled.state_size(), 2);
  const double c = std::cos(0.5), s = std::sin(0.5), e = 0.03, f = -0.04;
  const Vec3 E(e * c * c + f * s * s, e * s * s + f * c * c, 2 * (e - f) * c * s);
  SheetResponse r;
  wrinkled.evaluate(E, h, r);
  ASSERT_EQ(r.state, WrinkleState::kWrinkled);
  const double err = (r.C - central_differences(wrinkled.base(), E, h)).cwiseAbs().maxCoeff() /
                     r.C.cwiseAbs().maxCoeff();
  std::printf("[stress map unloading] wrinkled: %.2e\n", err);
  EXPECT_LT(err, 1e-5);
}

TEST(StressMapUnloading, WithoutModuliThereIsNoHistoryAndSoftModuliAreRefused) {
  EXPECT_EQ(StressMapSheetLaw("pvc", fabric(0, 0)).state_size(), 0);
  EXPECT_EQ(StressMapSheetLaw("pvc", fabric(0, kFill)).state_size(), 2);
  auto message = [](double warp, double fill) {
    try {
      StressMapSheetLaw("pvc", fabric(warp, fill));
    } catch (const MaterialError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(700, kFill).find("warp unloading modulus 700 is below the map's steepest"),
            std::string::npos)
      << message(700, kFill);
  EXPECT_NE(message(kWarp, -1).find("must be positive"), std::string::npos);
}

}  // namespace
}  // namespace velum
