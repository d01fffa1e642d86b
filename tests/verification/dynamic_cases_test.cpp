// Verification B6-B8 (VERIFICATION.md section B): free vibration of a pre-stretched membrane,
// a large-amplitude pendulum on a stiff cable, and the implicit integrators on a linear
// oscillator (observed order and high-frequency spectral radius). Built through the Model
// API; suite `Solver`: the fast variants, suite `Verification`: the refinements.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "model_builders.hpp"

namespace velum::test {
namespace {

constexpr double kPi = std::numbers::pi;

// Period from the zero crossings (either direction, linear interpolation) of a sampled signal:
// 2 (t_last − t_first) / (crossings − 1). Crossings before `t_skip` are ignored.
double crossing_period(const std::vector<double>& t, const std::vector<double>& y,
                       double t_skip = 0) {
  std::vector<double> z;
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] > t_skip && ((y[i - 1] < 0) != (y[i] < 0)) && y[i] != y[i - 1])
      z.push_back(t[i - 1] + (t[i] - t[i - 1]) * y[i - 1] / (y[i - 1] - y[i]));
  if (z.size() < 2) return 0;
  return 2 * (z.back() - z.front()) / static_cast<double>(z.size() - 1);
}

// ---------------------------------------------------------------------------------------------
// B6 Pre-stretched square membrane: every boundary node carries the prescribed displacement
// (λ − 1) X of a homogeneous equibiaxial stretch. The homogeneous stretch is the exact static
// solution on any mesh, so the run starts from it, plus a small transverse displacement
// A sin(πx/a) sin(πy/a) (A = 1e-4 a), at rest. The centre's free response (Newmark,
// trapezoidal) gives the period from its zero crossings.
double prestretched_square(int n, std::string_view type, int steps_per_period, int periods) {
  const double a = 1.0, E = 1e9, t = 1e-3, nu = 0.3, rho = 1000, lambda = 1.05;
  Model m;
  NodeCache nodes(m, 1e-9 * a);
  auto conn = square(nodes, a, n, type);
  add_membrane(m, type, std::move(conn), PlaneStressLaw::isotropic("film", E, nu), rho, t);
  for (int k : nodes_where(m, [&](const Vec3& X) {
         return std::min({X.x(), X.y(), a - X.x(), a - X.y()}) < 1e-9 * a;
       }))
    m.prescribed.push_back({{k}, (lambda - 1) * m.X.col(k), -1});
  MechanicalSystem sys(m);
  NodePositions U = (lambda - 1) * m.X;
  for (int k = 0; k < m.num_nodes(); ++k)
    U(2, k) = 1e-4 * a * std::sin(kPi * m.X(0, k) / a) * std::sin(kPi * m.X(1, k) / a);
  State s = state_from(sys, U);

  const double S = E * t * (lambda * lambda - 1) / (2 * (1 - nu));
  const double f11 = std::sqrt(2.0) / (2 * a) * std::sqrt(S / (rho * t));
  const double T = 1 / f11;
  auto integrator = GeneralizedAlpha::newmark();
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t_end = periods * T;
  loop.step = T / steps_per_period;
  const int centre = nearest_node(m, Vec3(0.5 * a, 0.5 * a, 0));
  std::vector<double> ts{0}, ws{U(2, centre)};
  const TimeLoopResult res = run_time_loop(
      sys, *integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& cur) {
        ts.push_back(st.t);
        ws.push_back(sys.displacements(st.t, cur.u)(2, centre));
        return true;
      });
  EXPECT_TRUE(res.completed) << res.reason;
  const double Tm = crossing_period(ts, ws);
  const double err = percent(Tm, T);
  fmt::print(
      "B6 f11 error {:.4f}% ({} {}x{}, {} dofs, h = T/{}, {} periods, {} Newton its): "
      "f = {:.4f} Hz, analytic {:.4f} Hz\n",
      err, type, n, n, sys.size(), steps_per_period, periods, res.iterations, 1 / Tm, f11);
  return err;
}

TEST(Solver, B6PrestretchedMembrane) {
  EXPECT_LT(prestretched_square(6, "quad9", 60, 4), 0.5);
}

TEST(Verification, B6PrestretchedMembraneRefined) {
  EXPECT_LT(prestretched_square(12, "quad9", 100, 6), 0.5);
  EXPECT_LT(prestretched_square(24, "quad4", 100, 6), 0.5);
}

// ---------------------------------------------------------------------------------------------
// B7 Pendulum: a massless stiff cable (E A = 1e6 m g, so the static stretch is 1e-6 L) with a
// payload released at rest from θ0 = 60°; trapezoidal rule (Newmark β = ¼, γ = ½) through
// run_analysis. Period from the zero crossings of the payload's x; energy balance
// K + U − W_ext from the analysis' own bookkeeping.
void pendulum(int steps_per_period, int periods) {
  const double L = 1.0, g = 9.81, mass = 1.0, theta0 = kPi / 3;
  Model m;
  const int top = m.add_node(1, Vec3::Zero());
  const int bob = m.add_node(2, Vec3(L * std::sin(theta0), 0, -L * std::cos(theta0)));
  add_cable(m, "cable2", {top, bob}, CableLaw{1e6 * mass * g, false}, 0.0, 1.0);
  m.masses.push_back({bob, mass, 0, 0});
  m.fixed.push_back({{top}, {true, true, true}});
  m.gravity.push_back({Vec3(0, 0, -g), -1});
  MechanicalSystem sys(m);

  const double T0 = 2 * kPi * std::sqrt(L / g), T = 1.073182 * T0;
  AnalysisSettings as;
  as.type = AnalysisSettings::Type::kDynamic;
  as.scheme = "newmark";
  as.time.t_end = periods * T;
  as.time.step = T / steps_per_period;
  const double scale = mass * g * L * (1 - std::cos(theta0));  // largest kinetic energy
  std::vector<double> ts, xs, balance;
  const AnalysisResult res = run_analysis(sys, as, [&](const StepSnapshot& snap) {
    ts.push_back(snap.step.t);
    xs.push_back(sys.displacements(snap.step.t, snap.state.u)(0, bob) + m.X(0, bob));
    balance.push_back((snap.energy.kinetic + snap.energy.strain - snap.energy.external_work) /
                      scale);
    return true;
  });
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  const double ratio = crossing_period(ts, xs) / T0;
  const double err = percent(ratio, 1.073182);
  double worst = 0;
  for (double b : balance) worst = std::max(worst, std::abs(b - balance.front()));
  const double drift = std::abs(balance.back() - balance.front()) / periods;
  fmt::print(
      "B7 period error {:.4f}% (h = T/{}, {} periods, {} Newton its): T/T0 = {:.6f}; "
      "energy drift {:.2e}% per period of m g L (1 - cos θ0), largest excursion {:.2e}%\n",
      err, steps_per_period, periods, res.loop.iterations, ratio, 100 * drift, 100 * worst);
  EXPECT_LT(err, 0.5);
  EXPECT_LT(drift, 1e-3);
}

TEST(Solver, B7Pendulum) {
  pendulum(100, 3);
}
TEST(Verification, B7PendulumRefined) {
  pendulum(400, 10);
}

// ---------------------------------------------------------------------------------------------
// B8 Integrators on a linear oscillator: a truss (cable2 carrying compression) of stiffness
// k = E A / L = 4π² with a unit point mass (ω = 2π, period 1), moved along its axis only.
// Displacements stay at 1e-6 L, where the Green-strain truss is linear to 1e-6.
struct Oscillator {
  Model model;
  int node = -1;
  double k = 4 * kPi * kPi, mass = 1;
};

std::unique_ptr<Oscillator> oscillator(double force) {
  auto o = std::make_unique<Oscillator>();
  Model& m = o->model;
  const int n0 = m.add_node(1, Vec3::Zero());
  o->node = m.add_node(2, Vec3(1, 0, 0));
  add_cable(m, "cable2", {n0, o->node}, CableLaw{o->k, true}, 0.0, 1.0);
  m.masses.push_back({o->node, o->mass, 0, 0});
  m.fixed.push_back({{n0}, {true, true, true}});
  m.fixed.push_back({{o->node}, {false, true, true}});
  if (force != 0) m.point_loads.push_back({{o->node}, Vec3(force, 0, 0), -1});
  return o;
}

AnalysisSettings scheme_settings(const std::string& scheme, double param) {
  AnalysisSettings as;
  as.type = AnalysisSettings::Type::kDynamic;
  as.scheme = scheme;
  if (scheme == "hht") as.hht_alpha = param;
  if (scheme == "generalized-alpha") as.rho_inf = param;
  as.newton.tolerance = 1e-9;  // Green strain of a 1e-6 stretch holds ~10 digits
  as.newton.abs_residual = 0;
  return as;
}

// Step response from rest under a constant force F, u(t_end)/(F/k) with N steps; the linear
// solution is 1 − cos ω t_end.
double step_response(const std::string& scheme, double param, int N,
                     double* stable_step = nullptr) {
  const double F = 4 * kPi * kPi * 1e-6, t_end = 1.25;
  auto o = oscillator(F);
  MechanicalSystem sys(o->model);
  AnalysisSettings as = scheme_settings(scheme, param);
  as.time.t_end = t_end;
  as.time.step = t_end / N;
  as.time.adaptive = false;
  double u = 0;
  const AnalysisResult res = run_analysis(sys, as, [&](const StepSnapshot& snap) {
    u = snap.state.u[0];
    return true;
  });
  EXPECT_TRUE(res.loop.completed) << res.loop.reason;
  if (stable_step) *stable_step = res.stable_step;
  return u / (F / o->k);
}

// Spectral radius of the one-step amplification matrix of (u, h v, h² a) at ω h = wh,
// assembled column by column from single steps of amplitude ±δ (central differences cancel
// the truss's quadratic nonlinearity; the double root at infinity makes the eigenvalues
// sensitive to the square root of any error in the matrix). The double root also makes the
// radius approach ρ∞ slowly, as (ω h)^(-1/2): ρ∞ + 8e-5 at ω h = 1e6 for ρ∞ = 0.8.
double spectral_radius(TimeIntegrator& integrator, double wh) {
  auto o = oscillator(0);
  MechanicalSystem sys(o->model);
  auto solver = make_linear_solver(SolverKind::kAuto);
  const double h = wh / std::sqrt(o->k / o->mass), delta = 1e-4;
  auto step = [&](int j, double d) {
    State s;
    s.u = VecX::Constant(1, j == 0 ? d : 0);
    s.v = VecX::Constant(1, j == 1 ? d / h : 0);
    s.a = VecX::Constant(1, j == 2 ? d / (h * h) : 0);
    const StepReport rep = integrator.step(sys, *solver, 0.0, h, s);
    EXPECT_TRUE(rep.converged) << rep.reason;
    return Vec3(s.u[0], s.v[0] * h, s.a[0] * h * h);
  };
  Eigen::Matrix3d A;
  for (int j = 0; j < 3; ++j) A.col(j) = (step(j, delta) - step(j, -delta)) / (2 * delta);
  return A.eigenvalues().cwiseAbs().maxCoeff();
}

struct SchemeCase {
  std::string scheme;
  double param, rho_inf;
};

void integrators(const std::vector<int>& steps) {
  const std::vector<SchemeCase> cases{{"newmark", 0, 1.0},
                                      {"hht", 0.1, 0.9 / 1.1},
                                      {"hht", 0.3, 0.7 / 1.3},
                                      {"generalized-alpha", 0.8, 0.8},
                                      {"generalized-alpha", 0.5, 0.5},
                                      {"generalized-alpha", 0.0, 0.0}};
  for (const auto& c : cases) {
    // Observed order by self-convergence, d(N) = |u(N) − u(2N)| and log2(d(N)/d(2N)): the
    // truss's 1e-6 nonlinearity (a frequency shift of the same order, which the comparison with
    // the linear solution would see) cancels. The error against the linear solution is printed.
    std::vector<double> u;
    for (int N : steps) u.push_back(step_response(c.scheme, c.param, N));
    u.push_back(step_response(c.scheme, c.param, 2 * steps.back()));
    const double exact = 1 - std::cos(2 * kPi * 1.25);
    std::string orders;
    double last = 0;
    for (size_t i = 0; i + 2 < u.size(); ++i) {
      last = std::log2(std::abs(u[i] - u[i + 1]) / std::abs(u[i + 1] - u[i + 2]));
      orders += fmt::format(" {:.3f}", last);
    }
    const double e0 = std::abs(u.front() - exact), e1 = std::abs(u[u.size() - 2] - exact);
    auto integ = make_integrator(scheme_settings(c.scheme, c.param));
    const double rho = spectral_radius(*integ, 1e6);
    fmt::print(
        "B8 {} ({}): error vs linear solution at h = 1.25/{}..1.25/{}: {:.2e} .. {:.2e}, "
        "self-convergence orders{}; spectral radius at omega h = 1e6: {:.5f} (rho_inf {:.5f})\n",
        c.scheme, c.param, steps.front(), steps.back(), e0, e1, orders, rho, c.rho_inf);
    EXPECT_NEAR(last, 2.0, 0.1) << c.scheme << " " << c.param;
    EXPECT_NEAR(rho, c.rho_inf, 1e-3) << c.scheme << " " << c.param;
  }
}

TEST(Solver, B8Integrators) {
  integrators({20, 40, 80, 160});
}
TEST(Verification, B8IntegratorsRefined) {
  integrators({40, 80, 160, 320, 640});
}

// Explicit central difference on the B8 oscillator: the stable-step estimate is 2/ω (the
// lumped mass sits on one DOF), the run uses 0.9 of it, and the step response converges at
// second order in h to 1 − cos ω t.
TEST(Solver, CentralDifferenceStableStepAndOrder) {
  const double t_end = 1.25;  // as in step_response
  double stable = 0;
  const double exact = 1 - std::cos(2 * kPi * t_end);
  const double e1 = std::abs(step_response("central-difference", 0, 200, &stable) - exact);
  const double e2 = std::abs(step_response("central-difference", 0, 400) - exact);
  const double order = std::log2(e1 / e2);
  std::cout << "central difference: stable step " << stable << " (2/ω = " << 1 / kPi << "), errors "
            << e1 << ", " << e2 << ", observed order " << order << "\n";
  EXPECT_NEAR(stable, 1 / kPi, 1e-3 / kPi);
  EXPECT_NEAR(order, 2.0, 0.1);
}

}  // namespace
}  // namespace velum::test
