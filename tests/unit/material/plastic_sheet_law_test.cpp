// The elastic-plastic sheet (ETFE): its algorithmic tangent equals central differences of the
// return-mapped stress, and that stress those of its incremental potential, in elastic and
// plastic states from virgin and from plastically strained histories (bilinear, tabulated and
// perfectly plastic hardening); a uniaxial load-unload-reverse cycle in plane stress (S22 = 0
// by Newton on E22) against the closed form of linear isotropic hardening: the hardening
// branch, elastic unloading, the residual strain and the reverse yield at −σ_y(α_max);
// constants and curves that cannot work are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "fd_error.hpp"
#include "velum/material/plane_stress.hpp"
#include "velum/material/plastic_sheet_law.hpp"
#include "velum/material/sheet_law.hpp"

namespace velum {
namespace {

constexpr double kEtfeModulus = 1.1e9, kEtfePoisson = 0.45, kYield = 16e6, kH = 6e7;

PlasticSheetLaw bilinear() {
  return PlasticSheetLaw::bilinear("etfe", kEtfeModulus, kEtfePoisson, kYield, kH);
}
PlasticSheetLaw tabulated() {
  return PlasticSheetLaw::tabulated("etfe", kEtfeModulus, kEtfePoisson,
                                    {{0, 16e6}, {0.01, 19e6}, {0.05, 23e6}, {0.3, 30e6}});
}
PlasticSheetLaw perfect() {
  return PlasticSheetLaw::tabulated("etfe", kEtfeModulus, kEtfePoisson, {{0, 16e6}});
}

FdError fd_error(const PlasticSheetLaw& law, const Vec3& E, std::span<const double> h) {
  SheetResponse r;
  law.evaluate(E, h, r);
  Mat3 C_fd;
  Vec3 S_fd;
  const double d = 1e-8;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += d;
    Em[j] -= d;
    SheetResponse rp, rm;
    law.evaluate(Ep, h, rp);
    law.evaluate(Em, h, rm);
    C_fd.col(j) = (rp.S - rm.S) / (2 * d);
    S_fd[j] = (law.energy(Ep, h) - law.energy(Em, h)) / (2 * d);
  }
  return {(r.C - C_fd).cwiseAbs().maxCoeff() / r.C.cwiseAbs().maxCoeff(),
          (r.S - S_fd).cwiseAbs().maxCoeff() / r.S.cwiseAbs().maxCoeff()};
}

TEST(PlasticSheetLaw, AlgorithmicTangentMatchesFiniteDifferences) {
  double worst_tangent = 0, worst_stress = 0;
  for (const PlasticSheetLaw& law : {bilinear(), tabulated(), perfect()}) {
    // A plastically strained history: the state after a biaxial, sheared step (not one of the
    // strains below: at the very strain of its last step a point sits on the kink between
    // unloading and loading, where no derivative exists).
    double h[4];
    law.initial_state(h);
    law.update_state(Vec3(0.025, 0.012, 0.018), h);
    EXPECT_GT(h[3], 0.0);
    const double virgin[4] = {0, 0, 0, 0};
    for (const double* hist : {static_cast<const double*>(virgin), static_cast<const double*>(h)}) {
      for (const Vec3& E :
           {Vec3(0.004, -0.002, 0.003), Vec3(0.03, 0.01, 0.02), Vec3(0.05, -0.01, -0.03),
            Vec3(0.002, 0.001, 0.0005), Vec3(0.08, 0.07, 0.01)}) {
        const std::span<const double> hs(hist, 4);
        const PlasticSheetLaw::Return ret = law.return_map(E, hs);
        const FdError err = fd_error(law, E, hs);
        worst_tangent = std::max(worst_tangent, err.tangent);
        worst_stress = std::max(worst_stress, err.stress);
        EXPECT_LT(err.tangent, 1e-5) << E.transpose() << " dgamma " << ret.dgamma;
        EXPECT_LT(err.stress, 1e-5) << E.transpose();
        EXPECT_LT((ret.C - ret.C.transpose()).norm(), 1e-9 * ret.C.norm());
        // On the yield surface after a plastic step: σ_eq = σ_y(α).
        if (ret.dgamma > 0) {
          const Vec3& S = ret.S;
          const double seq = std::sqrt(S[0] * S[0] + S[1] * S[1] - S[0] * S[1] + 3 * S[2] * S[2]);
          EXPECT_NEAR(seq, law.yield_stress(ret.alpha), 1e-9 * seq);
        }
      }
    }
  }
  std::printf("plastic law: worst relative FD error of the tangent %.2e, of the stress %.2e\n",
              worst_tangent, worst_stress);
  // Elastic states return the elastic law.
  SheetResponse r;
  bilinear().evaluate(Vec3(0.001, 0.0, 0.0), {}, r);
  EXPECT_EQ(r.C, PlaneStressLaw::isotropic("q", kEtfeModulus, kEtfePoisson).Q());
}

/// Uniaxial stress S = (s, 0, 0) at E11 = e: E22 solved for S22 = 0 from history h.
Vec3 uniaxial(const PlasticSheetLaw& law, double e, std::span<const double> h, double guess,
              SheetResponse& r) {
  Vec3 E(e, guess, 0);
  for (int it = 0; it < 50; ++it) {
    law.evaluate(E, h, r);
    if (std::abs(r.S[1]) < 1e-6) break;
    E[1] -= r.S[1] / r.C(1, 1);
  }
  return E;
}

TEST(PlasticSheetLaw, UniaxialLoadUnloadCycleMatchesTheClosedForm) {
  const PlasticSheetLaw law = bilinear();
  double h[4] = {0, 0, 0, 0};
  const double ey = kYield / kEtfeModulus, emax = 0.04;
  // Loading: s = E e up to yield, then s = (σ_y0 + H e)/(1 + H/E).
  auto loading = [&](double e) {
    return e <= ey ? kEtfeModulus * e : (kYield + kH * e) / (1 + kH / kEtfeModulus);
  };
  const double smax = loading(emax), amax = emax - smax / kEtfeModulus;
  auto closed = [&](double e, int phase) {
    if (phase == 0) return loading(e);
    const double s = smax - kEtfeModulus * (emax - e);  // elastic unloading
    const double sy = kYield + kH * amax;               // reverse yield at −σ_y(α_max)
    if (s >= -sy) return s;
    // Reverse hardening: α grows from α_max as the plastic strain falls below α_max.
    // s = −(σ_y0 + H α), e = s/E + ε_p, ε_p = α_max − (α − α_max).
    return -(kYield + kH * (2 * amax - e)) / (1 + kH / kEtfeModulus);
  };
  double worst = 0, e22 = 0;
  int steps = 0;
  auto drive = [&](double e, int phase) {
    SheetResponse r;
    const Vec3 E = uniaxial(law, e, h, e22, r);
    e22 = E[1];
    worst = std::max(worst, std::abs(r.S[0] - closed(e, phase)) / smax);
    law.update_state(E, h);
    ++steps;
    return r.S[0];
  };
  for (int k = 1; k <= 40; ++k) drive(emax * k / 40, 0);
  // Unloaded to zero stress: the strain left is α_max (the plastic strain along the load).
  const double eres = emax - smax / kEtfeModulus;
  for (int k = 1; k <= 20; ++k) drive(emax + (eres - emax) * k / 20, 1);
  SheetResponse r;
  uniaxial(law, eres, h, e22, r);
  EXPECT_NEAR(r.S[0], 0, 1e-6 * smax);
  EXPECT_NEAR(h[0], eres, 1e-12);
  EXPECT_NEAR(h[3], amax, 1e-12);
  // On, into compression and reverse yield.
  const double emin = eres - 0.03;
  for (int k = 1; k <= 30; ++k) drive(eres + (emin - eres) * k / 30, 1);
  std::printf(
      "uniaxial cycle: %d steps, worst stress error %.2e of the peak; residual strain "
      "%.6f (closed form %.6f)\n",
      steps, worst, eres, amax);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(h[3], amax);  // yielded again in reverse
}

TEST(PlasticSheetLaw, WrinkledFoilYieldsInUniaxialTensionAlongTheWrinkles) {
  // Stretched along θ past yield, pushed together across: the tension field of the plastic
  // law is its uniaxial state along θ, S_nn = (σ_y0 + H e)/(1 + H/E), and the history moves on
  // at the elastic strain (the uniaxial plastic strain e − S/E along θ).
  const SheetLaw law = SheetLaw(bilinear()).with_wrinkling(0);
  ASSERT_EQ(law.state_size(), 4);
  const double theta = 0.6, c = std::cos(theta), s = std::sin(theta), e = 0.03, f = -0.05;
  const Vec3 E(e * c * c + f * s * s, e * s * s + f * c * c, 2 * (e - f) * c * s);
  double h[4];
  law.base().initial_state(h);
  SheetResponse r;
  law.evaluate(E, h, r);
  ASSERT_EQ(r.state, WrinkleState::kWrinkled);
  const double S = (kYield + kH * e) / (1 + kH / kEtfeModulus);
  EXPECT_NEAR((r.S - S * Vec3(c * c, s * s, c * s)).cwiseAbs().maxCoeff(), 0, 1e-8 * S);
  // Its tangent against central differences.
  Mat3 C_fd;
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += 1e-8;
    Em[j] -= 1e-8;
    SheetResponse rp, rm;
    law.evaluate(Ep, h, rp);
    law.evaluate(Em, h, rm);
    C_fd.col(j) = (rp.S - rm.S) / 2e-8;
  }
  const double err = (r.C - C_fd).cwiseAbs().maxCoeff() / r.C.cwiseAbs().maxCoeff();
  std::printf("wrinkled plastic foil: relative FD error of the tangent %.2e\n", err);
  EXPECT_LT(err, 1e-5);
  law.base().update_state(E, h);
  EXPECT_NEAR(h[3], e - S / kEtfeModulus, 1e-9);  // α = the uniaxial plastic strain along θ
  const double ep_nn = h[0] * c * c + h[1] * s * s + h[2] * c * s;
  EXPECT_NEAR(ep_nn, e - S / kEtfeModulus, 1e-9);
}

TEST(PlasticSheetLaw, BadConstantsAndCurvesAreRefused) {
  auto message = [](auto f) {
    try {
      f();
    } catch (const MaterialError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] {
              PlasticSheetLaw::bilinear("f", kEtfeModulus, kEtfePoisson, 0, kH);
            }).find("yield stress"),
            std::string::npos);
  EXPECT_NE(message([] {
              PlasticSheetLaw::bilinear("f", kEtfeModulus, kEtfePoisson, kYield, -1);
            }).find("hardening modulus"),
            std::string::npos);
  EXPECT_NE(message([] {
              PlasticSheetLaw::tabulated("f", kEtfeModulus, kEtfePoisson, {{0, 1e6}, {0, 2e6}});
            }).find("must ascend"),
            std::string::npos);
  EXPECT_NE(message([] {
              PlasticSheetLaw::tabulated("f", kEtfeModulus, kEtfePoisson, {{0, 2e6}, {0.1, 1e6}});
            }).find("falls"),
            std::string::npos);
  EXPECT_NE(message([] {
              PlasticSheetLaw::tabulated("f", kEtfeModulus, kEtfePoisson, {{0.01, 2e6}});
            }).find("start at plastic strain 0"),
            std::string::npos);
  EXPECT_NE(
      message([] { PlasticSheetLaw::bilinear("f", -1, kEtfePoisson, kYield, kH); }).find("'f'"),
      std::string::npos);
}

}  // namespace
}  // namespace velum
