// Gas flow in rigid vessels against closed forms (VERIFICATION.md F6): constant inflow, choked
// isentropic blowdown through a vent and its switch to unchoked flow, isothermal Darcy leakage,
// two vessels through an orifice; the first law closing to round-off in each, and the
// pressures' derivatives with respect to the volumes and leaking areas against differences.
#include <gtest/gtest.h>

#include <cmath>

#include "velum/load/gas_flow.hpp"

namespace velum::gas {
namespace {

constexpr double kR = 287.0, kGamma = 1.4;

Chamber chamber(double gamma, double T, double p0, double pa, int inflators) {
  Chamber c;
  c.gamma = gamma, c.R = kR, c.temperature = T, c.initial_pressure = p0, c.ambient = pa;
  c.inflators = inflators;
  return c;
}

struct Given {
  std::vector<double> V, A, inflow, inflow_T;
  Inputs in() const { return {V, A, inflow, inflow_T}; }
};

// U − U0 − (H_in − H_out − W), relative to the largest term.
double first_law_error(const Network& net, int c) {
  const Account& a = net.account(c);
  const double U = net.committed().E[c] / (net.chamber(c).gamma - 1);
  const double scale =
      std::max({std::abs(U), std::abs(a.U0), a.enthalpy_in, a.enthalpy_out, std::abs(a.work)});
  return std::abs(U - a.U0 - (a.enthalpy_in - a.enthalpy_out - a.work)) / scale;
}

TEST(GasFlow, ConstantInflowIntoARigidVessel) {
  Chamber c = chamber(kGamma, 300, 1e5, 1e5, 1);
  Network net({c}, {});
  const double V = 0.02, mdot = 0.05, Ti = 600;
  Given r{{V}, {}, {mdot}, {Ti}};
  net.start(0, r.in());
  const double cv = kR / (kGamma - 1), cp = kGamma * cv;
  const double m0 = 1e5 * V / (kR * 300);
  double worst = 0;
  for (int k = 1; k <= 100; ++k) {
    const double t = 1e-3 * k;
    net.commit(t, r.in());
    const double m = m0 + mdot * t;
    const double T = (m0 * cv * 300 + mdot * cp * Ti * t) / (m * cv);
    const double p = m * kR * T / V;
    worst = std::max(worst, std::abs(net.committed().p[0] - p) / p);
    EXPECT_NEAR(net.committed().m[0], m, 1e-13 * m);
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(first_law_error(net, 0), 1e-13);
  std::printf("constant inflow: largest relative pressure error %.3g\n", worst);
}

// The isentropic blowdown of a rigid vessel as an ODE in (m, U), integrated by RK4 with a
// fine step: the reference after the switch to unchoked flow.
double blowdown_reference(double p0, double T0, double V, double CdA, double pa, double t_end) {
  double m = p0 * V / (kR * T0), U = p0 * V / (kGamma - 1);
  auto f = [&](double mm, double UU, double& dm, double& dU) {
    const double p = (kGamma - 1) * UU / V, rho = mm / V;
    const double mdot = p > pa ? CdA * std::sqrt(rho * p) * orifice_function(kGamma, pa / p) : 0;
    dm = -mdot;
    dU = -mdot * kGamma / (kGamma - 1) * p / rho;  // U' = −ṁ cp T, cp T = γ/(γ−1) p/ρ
  };
  const int n = 200000;
  const double h = t_end / n;
  for (int i = 0; i < n; ++i) {
    double a1, b1, a2, b2, a3, b3, a4, b4;
    f(m, U, a1, b1);
    f(m + 0.5 * h * a1, U + 0.5 * h * b1, a2, b2);
    f(m + 0.5 * h * a2, U + 0.5 * h * b2, a3, b3);
    f(m + h * a3, U + h * b3, a4, b4);
    m += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    U += h / 6 * (b1 + 2 * b2 + 2 * b3 + b4);
  }
  return (kGamma - 1) * U / V;
}

TEST(GasFlow, ChokedBlowdownThenUnchoked) {
  const double V = 0.01, p0 = 6e5, T0 = 300, pa = 1e5, A = 2e-5, Cd = 0.8;
  Chamber c = chamber(kGamma, T0, p0, pa, 0);
  c.vents.push_back({.area = A, .discharge = Cd});
  Network net({c}, {});
  Given r{{V}, {}, {}, {}};
  net.start(0, r.in());
  const double c0 = std::sqrt(kGamma * kR * T0);
  const double K = std::pow((kGamma + 1) / 2, -(kGamma + 1) / (2 * (kGamma - 1)));
  const double tau = V / (Cd * A * c0 * K);
  const double critical = std::pow((kGamma + 1) / 2, kGamma / (kGamma - 1));
  const double h = tau / 400;
  double worst = 0, t = 0, t_switch = -1;
  while (net.committed().p[0] > 1.2 * pa) {
    t += h;
    net.commit(t, r.in());
    const double p = net.committed().p[0];
    if (p / pa >= critical) {
      const double exact =
          p0 * std::pow(1 + (kGamma - 1) / 2 * t / tau, -2 * kGamma / (kGamma - 1));
      worst = std::max(worst, std::abs(p - exact) / exact);
    } else if (t_switch < 0) {
      t_switch = t;
    }
  }
  EXPECT_LT(worst, 2e-3 * 0.1);  // well inside the 0.2% of VERIFICATION F6
  ASSERT_GT(t_switch, 0);
  // Past the switch: against the ODE's fine reference, and the vent's flow the unchoked one.
  const double ref = blowdown_reference(p0, T0, V, Cd * A, pa, t);
  const double p = net.committed().p[0];
  EXPECT_LT(std::abs(p - ref) / ref, 1e-4);
  const double rho = net.committed().m[0] / V, r_ = pa / p;
  const double unchoked =
      Cd * A * p / std::sqrt(p / rho) *
      std::sqrt(2 * kGamma / (kGamma - 1) *
                (std::pow(r_, 2 / kGamma) - std::pow(r_, (kGamma + 1) / kGamma)));
  EXPECT_NEAR(net.committed().rate[net.vent_flow(0, 0)], unchoked, 1e-12 * unchoked);
  // Φ is continuous at the critical ratio.
  const double rc = 1 / critical;
  EXPECT_NEAR(orifice_function(kGamma, rc * (1 + 1e-9)), orifice_function(kGamma, rc), 1e-9);
  EXPECT_LT(first_law_error(net, 0), 1e-13);
  std::printf(
      "choked blowdown: largest relative error %.3g (tau %.4g); after the switch at "
      "t = %.4g: %.3g against the fine ODE\n",
      worst, tau, t_switch, std::abs(p - ref) / ref);
}

TEST(GasFlow, IsothermalDarcyLeakage) {
  const double V = 0.05, p0 = 1.5e5, pa = 1e5, k = 2e-6, A = 0.4, T0 = 293;
  Chamber c = chamber(1, T0, p0, pa, 0);
  c.leaks.push_back({.permeability = k});
  Network net({c}, {});
  Given r{{V}, {A}, {}, {}};
  net.start(0, r.in());
  const double rate = k * A * pa / V;
  const double h = 0.01 / rate;
  double worst = 0;
  for (int s = 1; s <= 300; ++s) {
    const double t = s * h;
    net.commit(t, r.in());
    const double p = net.committed().p[0];
    const double q = (p - pa) / p, exact = (p0 - pa) / p0 * std::exp(-rate * t);
    worst = std::max(worst, std::abs(q - exact) / exact);
    EXPECT_NEAR(net.committed().E[0], net.committed().m[0] * kR * T0, 1e-12 * p * V);
  }
  EXPECT_LT(worst, 3e-3 * 0.1);
  // Mass: what left is what is missing.
  const Account& a = net.account(0);
  EXPECT_NEAR(a.mass0 - a.mass_out, net.committed().m[0], 1e-14 * a.mass0);
  std::printf("isothermal Darcy leakage: largest relative error %.3g\n", worst);
}

TEST(GasFlow, TwoVesselsThroughAnOrificeShareThePressure) {
  Chamber a = chamber(kGamma, 400, 3e5, 1e5, 0);
  Chamber b = chamber(kGamma, 300, 1.2e5, 1e5, 0);
  Network net({a, b}, {{.from = 0, .to = 1, .area = 1e-4, .discharge = 0.7}});
  Given r{{0.01, 0.03}, {}, {}, {}};
  net.start(0, r.in());
  const double m0 = net.committed().m[0] + net.committed().m[1];
  const double U0 = (net.committed().E[0] + net.committed().E[1]) / (kGamma - 1);
  for (int s = 1; s <= 400; ++s) net.commit(1e-3 * s, r.in());
  const Solution& now = net.committed();
  const double p_end = (kGamma - 1) * U0 / 0.04;
  EXPECT_NEAR(now.p[0], p_end, 1e-3 * p_end);
  EXPECT_NEAR(now.p[1], p_end, 1e-3 * p_end);
  EXPECT_NEAR(now.m[0] + now.m[1], m0, 1e-14 * m0);
  EXPECT_NEAR((now.E[0] + now.E[1]) / (kGamma - 1), U0, 1e-14 * U0);
  EXPECT_LT(first_law_error(net, 0), 1e-13);
  EXPECT_LT(first_law_error(net, 1), 1e-13);
  std::printf("two vessels: pressures %.8g and %.8g against %.8g; mass %.3g, energy %.3g\n",
              now.p[0], now.p[1], p_end, (now.m[0] + now.m[1] - m0) / m0,
              ((now.E[0] + now.E[1]) / (kGamma - 1) - U0) / U0);
}

TEST(GasFlow, DerivativesAgainstDifferences) {
  // Two chambers with an inflator, a vent, a quadratic leak and an orifice, mid-step.
  Chamber a = chamber(kGamma, 350, 2e5, 1e5, 1);
  a.vents.push_back({.area = 3e-5, .discharge = 0.9});
  a.leaks.push_back({.permeability = 1e-6, .quadratic = 2e3});
  Chamber b = chamber(kGamma, 300, 1.3e5, 1e5, 0);
  b.leaks.push_back({.permeability = 3e-6});
  Network net({a, b}, {{.from = 0, .to = 1, .area = 5e-5, .discharge = 0.6}});
  Given r{{0.01, 0.02}, {0.3, 0.5}, {0.02}, {700}};
  net.start(0, r.in());
  net.commit(1e-3, r.in());
  Given at{{0.0104, 0.0197}, {0.31, 0.49}, {0.03}, {700}};
  Solution s;
  net.solve(2e-3, at.in(), true, s);
  ASSERT_TRUE(s.ok);
  double worst = 0;
  for (int j = 0; j < 4; ++j) {
    Given plus = at, minus = at;
    double& xp = j < 2 ? plus.V[j] : plus.A[j - 2];
    double& xm = j < 2 ? minus.V[j] : minus.A[j - 2];
    const double d = 1e-6 * xp;
    xp += d, xm -= d;
    Solution sp, sm;
    net.solve(2e-3, plus.in(), false, sp);
    net.solve(2e-3, minus.in(), false, sm);
    for (int c = 0; c < 2; ++c) {
      const double fd = (sp.p[c] - sm.p[c]) / (2 * d);
      const double an = j < 2 ? s.dp_dV(c, j) : s.dp_dA(c, j - 2);
      const double scale = std::max(std::abs(s.dp_dV(c, c)) * 0.01, 1e-3 * std::abs(an));
      EXPECT_NEAR(an, fd, std::max(1e-6 * std::abs(an), 1e-7 * scale)) << c << " " << j;
      worst = std::max(worst, std::abs(an - fd) / std::max(std::abs(an), 1e-30));
    }
  }
  std::printf("gas flow dp/d(V, A) against central differences: worst relative %.3g\n", worst);
}

TEST(GasFlow, AdiabaticCompressionWithoutFlow) {
  // Without flow the trapezoidal work keeps p V^γ to second order in the step.
  Chamber c = chamber(kGamma, 300, 1e5, 1e5, 0);
  Network net({c}, {});
  Given r{{0.01}, {}, {}, {}};
  net.start(0, r.in());
  for (int s = 1; s <= 200; ++s) {
    r.V[0] = 0.01 * (1 - 0.5 * s / 200.0);
    net.commit(1e-3 * s, r.in());
  }
  const double exact = 1e5 * std::pow(2.0, kGamma);
  EXPECT_NEAR(net.committed().p[0], exact, 1e-4 * exact);
  EXPECT_LT(first_law_error(net, 0), 1e-13);
}

TEST(GasFlow, SaveAndRestoreGoOnAlike) {
  Chamber c = chamber(kGamma, 300, 3e5, 1e5, 1);
  c.vents.push_back({.area = 1e-5, .discharge = 1, .open_pressure = 2.5e5});
  Network a({c}, {}), b({c}, {});
  Given r{{0.01}, {}, {0.01}, {600}};
  a.start(0, r.in());
  b.start(0, r.in());
  for (int s = 1; s <= 10; ++s) a.commit(1e-3 * s, r.in());
  std::vector<double> saved;
  a.save(saved);
  EXPECT_EQ(b.restore(saved, 0), saved.size());
  a.commit(0.011, r.in());
  b.commit(0.011, r.in());
  EXPECT_EQ(a.committed().p[0], b.committed().p[0]);
}

}  // namespace
}  // namespace velum::gas
