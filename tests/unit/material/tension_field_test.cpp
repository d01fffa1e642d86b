// The tension-field (wrinkling) sheet law, VERIFICATION E3: a strain built from a known
// uniaxial stress plus a wrinkle contraction returns exactly that stress; the tangent equals
// central finite differences at wrinkled and slack states for every law, with the tension at
// 30° and 60° to the stiff axis; the tangent is symmetric and the stress is the gradient of
// the energy; taut states are the elastic law unchanged.
#include <gtest/gtest.h>

#include <numbers>

#include "../support.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/material/sheet_law.hpp"

namespace velum {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180;

std::vector<std::pair<std::string, PlaneStressLaw>> all_laws() {
  auto laws = test::test_laws();
  Mat3 Q;  // a general symmetric positive definite matrix law
  Q << 1800, 420, 150, 420, 900, -80, 150, -80, 350;
  laws.emplace_back("matrix", PlaneStressLaw::matrix("mat", Q));
  return laws;
}

/// Engineering-Voigt vectors of t⊗t and the stress-Voigt uniaxial stress s n⊗n at angle θ.
Vec3 vt_of(double th) {
  return {std::sin(th) * std::sin(th), std::cos(th) * std::cos(th), -std::sin(2 * th)};
}
Vec3 uniaxial(double s, double th) {
  const double c = std::cos(th), n = std::sin(th);
  return s * Vec3(c * c, n * n, c * n);
}

/// A strain whose trial stress is the uniaxial stress s n⊗n plus a wrinkle contraction β:
/// Q E + S0 = s n⊗n + β Q v_t (Q invertible).
Vec3 wrinkled_strain(const Mat3& Q, const Vec3& S0, double s, double beta, double th) {
  return Q.lu().solve(uniaxial(s, th) + beta * Q * vt_of(th) - S0);
}

Mat3 fd_tangent(const SheetLaw& law, const Vec3& E, double h) {
  Mat3 C;
  SheetResponse p, m;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += h;
    Em[j] -= h;
    law.evaluate(Ep, p);
    law.evaluate(Em, m);
    C.col(j) = (p.S - m.S) / (2 * h);
  }
  return C;
}

TEST(TensionField, E3UniaxialStressPlusWrinkleContractionIsRecoveredExactly) {
  for (const auto& [label, elastic] : all_laws()) {
    if (label == "fibers") continue;  // singular Q: no compliance to build the strain from
    for (const Vec3& S0 : {Vec3(0, 0, 0), Vec3(40, 25, 5)}) {
      const SheetLaw law = SheetLaw(elastic).with_prestress(S0).with_wrinkling(0.0);
      for (const double deg : {30.0, 60.0, 100.0, 145.0}) {
        for (const double beta : {-1e-3, -0.05}) {
          const double s = 12.0, th = deg * kRadiansPerDegree;
          const Vec3 E = wrinkled_strain(elastic.Q(), S0, s, beta, th);
          SheetResponse r;
          law.evaluate(E, r);
          ASSERT_EQ(r.state, WrinkleState::kWrinkled) << label << " " << deg;
          EXPECT_LT((r.S - uniaxial(s, th)).norm(), 1e-12 * s) << label << " " << deg;
          EXPECT_NEAR(std::remainder(r.angle - th, std::numbers::pi), 0, 1e-12) << label;
        }
      }
    }
  }
}

TEST(TensionField, TautStatesAreTheElasticLaw) {
  for (const auto& [label, elastic] : all_laws()) {
    const SheetLaw law = SheetLaw(elastic).with_wrinkling();
    const Vec3 E(0.01, 0.02, 0.001);  // both principal stresses positive for these laws
    SheetResponse r;
    law.evaluate(E, r);
    ASSERT_EQ(r.state, WrinkleState::kTaut) << label;
    // Exactly the law (for fibre sheets, up to the rounding of summing the families).
    EXPECT_LE((r.S - elastic.Q() * E).norm(), 1e-14 * r.S.norm()) << label;
    EXPECT_LE((r.C - elastic.Q()).norm(), 1e-14 * r.C.norm()) << label;
  }
}

TEST(TensionField, TangentMatchesFiniteDifferencesWhenWrinkledAndSlack) {
  test::Random rnd(7);
  for (const auto& [label, elastic] : all_laws()) {
    const Mat3& Q = elastic.Q();
    for (const Vec3& S0 : {Vec3(0, 0, 0), Vec3(30, 10, -4)}) {
      if (label == "fibers" && S0.squaredNorm() > 0) continue;  // refused: see below
      const SheetLaw law = SheetLaw(elastic).with_prestress(S0).with_wrinkling();
      std::vector<Vec3> strains;
      if (label != "fibers") {
        // The tension at 30° and 60° to the stiff axis m1 (E1 > E2 for every law here).
        for (const double deg : {30.0, 60.0})
          for (const double beta : {-2e-3, -0.03})
            strains.push_back(wrinkled_strain(Q, S0, 8.0, beta, deg * kRadiansPerDegree));
      }
      int wrinkled = 0, slack = 0;
      for (int k = 0; k < 400 && (wrinkled < 6 || slack < 3); ++k) {
        const Vec3 E = 0.1 * rnd.vec3(-1, 1);
        SheetResponse r;
        law.evaluate(E, r);
        if (r.state == WrinkleState::kWrinkled && wrinkled < 6) ++wrinkled, strains.push_back(E);
        if (r.state == WrinkleState::kSlack && slack < 3) ++slack, strains.push_back(E);
      }
      EXPECT_GE(wrinkled, 6) << label;
      EXPECT_GE(slack, 3) << label;
      for (const Vec3& E : strains) {
        SheetResponse r;
        law.evaluate(E, r);
        ASSERT_NE(r.state, WrinkleState::kTaut) << label;
        const Mat3 Cfd = fd_tangent(law, E, 1e-7 * E.norm());
        // The law's tangent is the tension field's derivative plus the residual stiffness
        // κ Q, which regularises the tangent only (the stress carries no compression).
        const Mat3 C_tf = r.C - law.slack_stiffness() * Q;
        const double scale =
            std::max(C_tf.cwiseAbs().maxCoeff(), law.slack_stiffness() * Q.cwiseAbs().maxCoeff());
        EXPECT_LT((C_tf - Cfd).cwiseAbs().maxCoeff() / scale, 1e-6)
            << label << " state " << int(r.state) << " E " << E.transpose();
        EXPECT_LT((r.C - r.C.transpose()).cwiseAbs().maxCoeff(), 1e-9 * scale) << label;
        // The stress is the gradient of the energy.
        Vec3 g;
        for (int j = 0; j < 3; ++j) {
          const double h = 1e-5 * E.norm();
          Vec3 Ep = E, Em = E;
          Ep[j] += h;
          Em[j] -= h;
          g[j] = (law.energy(Ep) - law.energy(Em)) / (2 * h);
        }
        EXPECT_LT((g - r.S).norm(), 1e-6 * std::max(r.S.norm(), 1e-3 * Q.norm() * E.norm()))
            << label;
      }
    }
  }
}

TEST(TensionField, FibreSheetsGoSlackFibreByFibre) {
  const auto fibers = PlaneStressLaw::fibers("f", {{1500.0, 0.0}, {900.0, 90.0}});
  const SheetLaw law = SheetLaw(fibers).with_wrinkling(0.0);
  SheetResponse r;
  law.evaluate(Vec3(0.01, -0.02, 0.005), r);  // the 0° family taut, the 90° family slack
  EXPECT_EQ(r.state, WrinkleState::kWrinkled);
  EXPECT_LT((r.S - Vec3(1500.0 * 0.01, 0, 0)).norm(), 1e-12);
  EXPECT_THROW(SheetLaw(fibers).with_wrinkling().with_prestress({1, 1, 0}), MaterialError);
}

TEST(TensionField, NoCompressionWhateverTheResidualStiffness) {
  test::Random rnd(11);
  for (const auto& [label, elastic] : all_laws()) {
    const SheetLaw law = SheetLaw(elastic).with_wrinkling();
    for (int k = 0; k < 200; ++k) {
      const Vec3 E = 0.05 * rnd.vec3(-1, 1);
      SheetResponse r;
      law.evaluate(E, r);
      const double mean = 0.5 * (r.S[0] + r.S[1]);
      const double min = mean - std::hypot(0.5 * (r.S[0] - r.S[1]), r.S[2]);
      const Vec3 St = elastic.Q() * E;
      EXPECT_GE(min, -1e-12 * St.norm()) << label << " " << E.transpose();
      if (r.state == WrinkleState::kSlack) {
        EXPECT_EQ(r.S.norm(), 0.0) << label;
      }
    }
  }
}

TEST(TensionField, SpuriousRootsWithNegativeTensionAreRejected) {
  // An orthotropic sheet with the tension at 60° to the stiff axis (the case Kratos's
  // projection leaves with principal stresses (4.03, −1.42)): the law's answer is uniaxial.
  const auto ortho = PlaneStressLaw::orthotropic("o", 10000, 1000, 0.3, 500, false);
  const SheetLaw law = SheetLaw(ortho).with_wrinkling(0.0);
  const double th = 60 * kRadiansPerDegree;
  const Vec3 E = wrinkled_strain(ortho.Q(), Vec3::Zero(), 4.0, -0.01, th);
  SheetResponse r;
  law.evaluate(E, r);
  ASSERT_EQ(r.state, WrinkleState::kWrinkled);
  const double mean = 0.5 * (r.S[0] + r.S[1]);
  const double rad = std::hypot(0.5 * (r.S[0] - r.S[1]), r.S[2]);
  EXPECT_NEAR(mean + rad, 4.0, 1e-12);
  EXPECT_NEAR(mean - rad, 0.0, 1e-12);
}

TEST(TensionField, IsotropicShortcutAgreesWithTheRootScan) {
  // An isotropic Q takes the closed-form root (the trial stress's major direction, one
  // Newton step); a Q made anisotropic by 1e-9 takes the general scan of H. Both must give
  // the same state, angle, stress and tangent to the perturbation's order, with and
  // without prestress, over random strains (wrinkled, slack and taut).
  const Mat3 Qiso = PlaneStressLaw::isotropic("iso", 1000.0, 0.3).Q();
  Mat3 Qnear = Qiso;
  Qnear(0, 0) *= 1 + 1e-9;
  test::Random rnd(5);
  int wrinkled = 0;
  for (const Vec3& S0 : {Vec3(0, 0, 0), Vec3(30, 10, -4)}) {
    for (int k = 0; k < 300; ++k) {
      const Vec3 E = 0.05 * rnd.vec3(-1, 1);
      const TensionField a = tension_field(Qiso, Qiso * E + S0);
      const TensionField b = tension_field(Qnear, Qnear * E + S0);
      ASSERT_EQ(a.state, b.state) << E.transpose();
      const double scale = Qiso.cwiseAbs().maxCoeff();
      EXPECT_LT((a.S - b.S).norm(), 1e-7 * std::max(b.S.norm(), 1e-3 * scale * E.norm()));
      EXPECT_LT((a.C - b.C).cwiseAbs().maxCoeff(), 1e-6 * scale) << E.transpose();
      if (a.state == WrinkleState::kWrinkled) {
        ++wrinkled;
        EXPECT_NEAR(std::remainder(a.angle - b.angle, std::numbers::pi), 0, 1e-6);
        EXPECT_GE(a.angle, 0);
        EXPECT_LT(a.angle, std::numbers::pi);
      }
    }
  }
  EXPECT_GE(wrinkled, 50);
}

}  // namespace
}  // namespace velum
