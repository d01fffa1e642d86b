// Incompressible hyperelastic sheets (neo-Hookean, Mooney-Rivlin): the tangent equals central
// differences of the stress and the stress those of the energy at finite anisotropic stretches,
// taut and wrinkled (the general tension field), with and without prestress; homogeneous
// equibiaxial and uniaxial stretches against their closed forms (the uniaxial one also as the
// tension field of a sheet pulled one way and pushed the other); the thickness follows
// h = H/(λ1 λ2); unstable constants are refused, naming the condition.
#include <gtest/gtest.h>

#include <cmath>

#include "fd_error.hpp"
#include "velum/material/incompressible_sheet_law.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/material/sheet_law_wrappers.hpp"

namespace velum {
namespace {

constexpr double kShearModulus = 2.0e5;

IncompressibleSheetLaw neo() {
  return IncompressibleSheetLaw::neo_hookean("rubber", kShearModulus);
}
IncompressibleSheetLaw mooney() {
  return IncompressibleSheetLaw::mooney_rivlin("mr", 0.5 * kShearModulus, 0.12 * kShearModulus);
}

/// Green-Lagrange strain (engineering Voigt) of principal stretches l1 along θ and l2 across.
Vec3 stretch_strain(double l1, double l2, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  const double e1 = 0.5 * (l1 * l1 - 1), e2 = 0.5 * (l2 * l2 - 1);
  return {e1 * c * c + e2 * s * s, e1 * s * s + e2 * c * c, 2 * (e1 - e2) * c * s};
}

FdError fd_error(const SheetLaw& law, const Vec3& E, double h = 1e-6) {
  SheetResponse r;
  law.evaluate(E, r);
  Mat3 C_fd;
  Vec3 S_fd;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += h;
    Em[j] -= h;
    SheetResponse rp, rm;
    law.evaluate(Ep, rp);
    law.evaluate(Em, rm);
    C_fd.col(j) = (rp.S - rm.S) / (2 * h);
    S_fd[j] = (law.energy(Ep) - law.energy(Em)) / (2 * h);
  }
  return {(r.C - C_fd).cwiseAbs().maxCoeff() / r.C.cwiseAbs().maxCoeff(),
          (r.S - S_fd).cwiseAbs().maxCoeff() / r.S.cwiseAbs().maxCoeff()};
}

TEST(IncompressibleSheetLaw, TangentAndStressMatchFiniteDifferencesAtFiniteStretches) {
  for (const SheetLaw& law : {SheetLaw(neo()), SheetLaw(mooney())}) {
    for (const Vec3& E : {Vec3(0.3, -0.1, 0.4), Vec3(1.2, 0.05, -0.3),
                          stretch_strain(2.5, 0.8, 0.7), Vec3(-0.2, -0.15, 0.1)}) {
      const FdError err = fd_error(law, E);
      EXPECT_LT(err.tangent, 1e-7) << law.name() << " at " << E.transpose();
      EXPECT_LT(err.stress, 1e-7) << law.name() << " at " << E.transpose();
      SheetResponse r;
      law.evaluate(E, r);
      EXPECT_LT((r.C - r.C.transpose()).norm(), 1e-10 * r.C.norm());  // a Hessian
    }
  }
}

TEST(IncompressibleSheetLaw, ReferenceStiffnessIsThePlaneStressLawOfNuOneHalf) {
  const IncompressibleSheetLaw law = mooney();
  const double mu = law.shear_modulus();
  const Mat3 Q = PlaneStressLaw::isotropic("q", 3 * mu, 0.4999999999).Q();
  EXPECT_NEAR((law.reference_stiffness() - Q).cwiseAbs().maxCoeff(), 0, 1e-6 * mu);
  SheetResponse r;
  law.evaluate(Vec3::Zero(), {}, r);
  EXPECT_EQ(r.S, Vec3::Zero());
  EXPECT_EQ(law.energy(Vec3::Zero(), {}), 0.0);
  EXPECT_FALSE(law.affine());
}

TEST(IncompressibleSheetLaw, EquibiaxialAndUniaxialStretchesMatchTheirClosedForms) {
  for (const IncompressibleSheetLaw& law : {neo(), mooney()}) {
    const double C1 = law.C1(), C2 = law.C2();
    for (double l : {0.8, 1.1, 1.5, 2.5, 4.0}) {
      // Equibiaxial: S = 2 (1 − λ⁻⁶)(C1 + C2 λ²), h/H = λ⁻².
      SheetResponse r;
      law.evaluate(stretch_strain(l, l, 0.3), {}, r);
      const double S = 2 * (1 - std::pow(l, -6)) * (C1 + C2 * l * l);
      EXPECT_NEAR(r.S[0], S, 1e-12 * kShearModulus);
      EXPECT_NEAR(r.S[1], S, 1e-12 * kShearModulus);
      EXPECT_NEAR(r.S[2], 0, 1e-12 * kShearModulus);
      EXPECT_NEAR(law.thickness_ratio(stretch_strain(l, l, 0.3), {}), 1 / (l * l), 1e-14);
      // Uniaxial: λ2 = λ^(−1/2) leaves S22 = 0 and S11 = 2 C1 (1 − λ⁻³) + 2 C2 (λ⁻¹ − λ⁻⁴).
      law.evaluate(stretch_strain(l, 1 / std::sqrt(l), 0), {}, r);
      EXPECT_NEAR(r.S[1], 0, 1e-12 * kShearModulus);
      EXPECT_NEAR(r.S[0], 2 * C1 * (1 - std::pow(l, -3)) + 2 * C2 * (1 / l - std::pow(l, -4)),
                  1e-12 * kShearModulus);
    }
  }
}

TEST(IncompressibleSheetLaw, TensionFieldIsTheUniaxialStateAlongTheStretch) {
  // Pulled to λ along θ and pushed to 0.6 < λ^(−1/2) across it: the sheet wrinkles along θ and
  // carries the uniaxial stress, its width relaxed to λ^(−1/2).
  for (const IncompressibleSheetLaw& base : {neo(), mooney()}) {
    const SheetLaw law = SheetLaw(base).with_wrinkling(0);
    EXPECT_TRUE(law.wrinkling());
    EXPECT_TRUE(law.thins());
    const double C1 = base.C1(), C2 = base.C2();
    for (double l : {1.2, 1.8, 2.5}) {
      for (double theta : {0.0, 0.4, 2.0}) {
        const Vec3 E = stretch_strain(l, 0.6, theta);
        SheetResponse r;
        law.evaluate(E, r);
        ASSERT_EQ(r.state, WrinkleState::kWrinkled);
        EXPECT_NEAR(std::remainder(r.angle - theta, M_PI), 0, 1e-9);
        const double s = 2 * C1 * (1 - std::pow(l, -3)) + 2 * C2 * (1 / l - std::pow(l, -4));
        const double c = std::cos(theta), sn = std::sin(theta);
        EXPECT_NEAR((r.S - s * Vec3(c * c, sn * sn, c * sn)).cwiseAbs().maxCoeff(), 0, 1e-9 * s);
        EXPECT_NEAR(law.thickness_ratio(E), 1 / std::sqrt(l), 1e-9);
        const FdError err = fd_error(law, E);
        EXPECT_LT(err.tangent, 1e-6) << l << " " << theta;
        EXPECT_LT(err.stress, 1e-7) << l << " " << theta;
      }
    }
    // Taut when stretched both ways; slack when compressed both ways.
    SheetResponse r;
    law.evaluate(stretch_strain(1.3, 1.1, 0.2), r);
    EXPECT_EQ(r.state, WrinkleState::kTaut);
    law.evaluate(stretch_strain(0.9, 0.8, 0.2), r);
    EXPECT_EQ(r.state, WrinkleState::kSlack);
    EXPECT_EQ(r.S, Vec3::Zero());
    EXPECT_EQ(law.energy(stretch_strain(0.9, 0.8, 0.2)), 0.0);
  }
}

TEST(IncompressibleSheetLaw, WrinkledTangentMatchesFiniteDifferencesWithPrestressAndShear) {
  const Vec3 S0(0.05 * kShearModulus, 0.02 * kShearModulus, 0.01 * kShearModulus);
  const SheetLaw law = SheetLaw(mooney()).with_prestress(S0).with_wrinkling(0);
  EXPECT_EQ(law.prestress(), S0);
  SheetResponse r;
  law.evaluate(Vec3::Zero(), r);
  EXPECT_EQ(r.S, S0);
  int wrinkled = 0;
  for (const Vec3& E : {Vec3(0.4, -0.2, 0.3), Vec3(0.1, -0.3, -0.25), Vec3(-0.1, 0.6, 0.5),
                        Vec3(0.05, 0.02, 0.01)}) {
    law.evaluate(E, r);
    wrinkled += r.state == WrinkleState::kWrinkled;
    const FdError err = fd_error(law, E);
    EXPECT_LT(err.tangent, 1e-6) << E.transpose();
    EXPECT_LT(err.stress, 1e-7) << E.transpose();
  }
  EXPECT_GE(wrinkled, 3);
  // Prestress given after wrinkling goes under the tension field all the same.
  const SheetLaw late = SheetLaw(mooney()).with_wrinkling().with_prestress(S0);
  SheetResponse a, b;
  law.evaluate(Vec3(0.4, -0.2, 0.3), a);
  late.evaluate(Vec3(0.4, -0.2, 0.3), b);
  EXPECT_EQ(a.S, b.S);
}

TEST(IncompressibleSheetLaw, UnstableConstantsAreRefusedNamingTheCondition) {
  auto message = [](auto f) {
    try {
      f();
    } catch (const MaterialError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(
      message([] { IncompressibleSheetLaw::neo_hookean("r", 0); }).find("mu must be positive"),
      std::string::npos);
  EXPECT_NE(message([] { IncompressibleSheetLaw::neo_hookean("r", -1); }).find("'r'"),
            std::string::npos);
  EXPECT_NE(message([] { IncompressibleSheetLaw::mooney_rivlin("r", 1, -2); }).find("C1 + C2"),
            std::string::npos);
  EXPECT_NE(message([] { IncompressibleSheetLaw::mooney_rivlin("r", -1, 2); }).find("C1 = -1"),
            std::string::npos);
  EXPECT_NE(message([] {
              IncompressibleSheetLaw::mooney_rivlin("r", 1, -0.25);
            }).find("sqrt(-C1/C2) = 2"),
            std::string::npos);
  EXPECT_NO_THROW(IncompressibleSheetLaw::mooney_rivlin("r", 1, 0));
  EXPECT_NO_THROW(IncompressibleSheetLaw::mooney_rivlin("r", 0, 1));
}

}  // namespace
}  // namespace velum
