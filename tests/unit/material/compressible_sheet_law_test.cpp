// The compressible neo-Hookean sheet (compressible_sheet_law.hpp) against closed forms:
// its small-strain stiffness is the plane-stress isotropic law of E = 2μ(1 + ν), ν; an
// equibiaxial stretch s gives S = μ (1 − C33/s²), a uniaxial stress along 1 (stretch a, the
// other two b) S11 = μ (1 − b²/a²) with S22 = 0, C33 and b the roots of μ (c − 1) + λ ln J = 0;
// the thickness ratio is λ3; near ν = 1/2 it tends to the incompressible sheet; its tangent
// equals central differences of its stress (anisotropic and wrinkled states) and its stress
// those of its energy.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "velum/material/compressible_sheet_law.hpp"
#include "velum/material/incompressible_sheet_law.hpp"
#include "velum/material/plane_stress.hpp"
#include "velum/material/sheet_law.hpp"

namespace velum {
namespace {

constexpr double kMu = 4.0e5, kNu = 0.3;

// The root of a rising f on (lo, hi) by bisection: independent of the law's Newton.
double root(const std::function<double(double)>& f, double lo, double hi) {
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

Mat3 central_differences(const SheetLawBase& law, const Vec3& E) {
  Mat3 C;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += 1e-7;
    Em[j] -= 1e-7;
    SheetResponse rp, rm;
    law.evaluate(Ep, {}, rp);
    law.evaluate(Em, {}, rm);
    C.col(j) = (rp.S - rm.S) / 2e-7;
  }
  return C;
}

TEST(CompressibleSheetLaw, SmallStrainStiffnessIsThePlaneStressIsotropicLaw) {
  const auto law = CompressibleSheetLaw::neo_hookean("film", kMu, kNu);
  const Mat3 Q = PlaneStressLaw::isotropic("film", 2 * kMu * (1 + kNu), kNu).Q();
  EXPECT_LT((law.reference_stiffness() - Q).cwiseAbs().maxCoeff(), 1e-9 * Q.norm());
  EXPECT_DOUBLE_EQ(law.thickness_ratio(Vec3::Zero(), {}), 1.0);
}

TEST(CompressibleSheetLaw, EquibiaxialAndUniaxialStretchesMatchTheClosedForms) {
  const auto law = CompressibleSheetLaw::neo_hookean("film", kMu, kNu);
  const double lam = law.lambda();
  double worst = 0;
  SheetResponse r;
  for (double s : {0.9, 1.05, 1.3, 1.8, 2.5}) {
    // Equibiaxial: C = s² I, C33 from μ (c − 1) + λ/2 ln(s⁴ c) = 0.
    const double c =
        root([&](double x) { return kMu * (x - 1) + 0.5 * lam * std::log(s * s * s * s * x); },
             1e-6, 10);
    const double e = 0.5 * (s * s - 1);
    law.evaluate(Vec3(e, e, 0), {}, r);
    const double S = kMu * (1 - c / (s * s));
    worst = std::max(
        {worst, std::abs(r.S[0] - S) / kMu, std::abs(r.S[1] - S) / kMu, std::abs(r.S[2]) / kMu});
    EXPECT_NEAR(law.thickness_ratio(Vec3(e, e, 0), {}), std::sqrt(c), 1e-12);
    // Uniaxial stress along 1: stretch a, b across in the plane and through the thickness,
    // μ (b² − 1) + λ ln(a b²) = 0.
    const double a = s;
    const double b =
        std::sqrt(root([&](double x) { return kMu * (x - 1) + lam * std::log(a * x); }, 1e-6, 10));
    law.evaluate(Vec3(0.5 * (a * a - 1), 0.5 * (b * b - 1), 0), {}, r);
    worst = std::max(
        {worst, std::abs(r.S[0] - kMu * (1 - b * b / (a * a))) / kMu, std::abs(r.S[1]) / kMu});
  }
  std::printf("[compressible neo-Hookean] closed forms: max relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(CompressibleSheetLaw, TendsToTheIncompressibleSheetNearNuOneHalf) {
  const auto nearly = CompressibleSheetLaw::neo_hookean("rubber", kMu, 0.49999);
  const auto incompressible = IncompressibleSheetLaw::neo_hookean("rubber", kMu);
  SheetResponse a, b;
  const Vec3 E(0.4, -0.1, 0.2);
  nearly.evaluate(E, {}, a);
  incompressible.evaluate(E, {}, b);
  const double err = (a.S - b.S).cwiseAbs().maxCoeff() / b.S.cwiseAbs().maxCoeff();
  EXPECT_LT(err, 1e-3) << a.S.transpose() << " / " << b.S.transpose();
  EXPECT_NEAR(nearly.thickness_ratio(E, {}), incompressible.thickness_ratio(E, {}), 1e-4);
}

TEST(CompressibleSheetLaw, TangentAndStressMatchCentralDifferences) {
  double worst = 0, worst_energy = 0;
  for (double nu : {0.0, 0.3, 0.45, -0.2}) {
    const auto law = CompressibleSheetLaw::neo_hookean("film", kMu, nu);
    for (const Vec3& E : {Vec3(0.1, -0.05, 0.08), Vec3(0.6, 0.2, -0.3), Vec3(-0.1, 0.3, 0.05),
                          Vec3(0.02, 0.0, 0.0)}) {
      SheetResponse r;
      law.evaluate(E, {}, r);
      worst = std::max(worst, (r.C - central_differences(law, E)).cwiseAbs().maxCoeff() /
                                  r.C.cwiseAbs().maxCoeff());
      Vec3 g;
      for (int j = 0; j < 3; ++j) {
        Vec3 Ep = E, Em = E;
        Ep[j] += 1e-7;
        Em[j] -= 1e-7;
        g[j] = (law.energy(Ep, {}) - law.energy(Em, {})) / 2e-7;
      }
      worst_energy = std::max(worst_energy, (g - r.S).cwiseAbs().maxCoeff() / kMu);
    }
  }
  std::printf("[compressible neo-Hookean] tangent %.2e, energy gradient %.2e\n", worst,
              worst_energy);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_energy, 1e-6);
  // Wrinkled: stretched along 0.4 rad, shortened across.
  const SheetLaw wrinkled =
      SheetLaw(CompressibleSheetLaw::neo_hookean("film", kMu, kNu)).with_wrinkling(0);
  const double c = std::cos(0.4), s = std::sin(0.4), e = 0.2, f = -0.1;
  const Vec3 E(e * c * c + f * s * s, e * s * s + f * c * c, 2 * (e - f) * c * s);
  SheetResponse r;
  wrinkled.evaluate(E, r);
  ASSERT_EQ(r.state, WrinkleState::kWrinkled);
  const double err = (r.C - central_differences(wrinkled.base(), E)).cwiseAbs().maxCoeff() /
                     r.C.cwiseAbs().maxCoeff();
  std::printf("[compressible neo-Hookean] wrinkled tangent %.2e\n", err);
  EXPECT_LT(err, 1e-5);
}

TEST(CompressibleSheetLaw, BadConstantsAreRefused) {
  auto message = [](double mu, double nu) {
    try {
      CompressibleSheetLaw::neo_hookean("film", mu, nu);
    } catch (const MaterialError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(-1, 0.3).find("mu must be positive"), std::string::npos);
  EXPECT_NE(message(kMu, 0.5).find("nu must lie in (-1, 0.5)"), std::string::npos);
}

}  // namespace
}  // namespace velum
