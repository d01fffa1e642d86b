// Verification B1-B5 (VERIFICATION.md section B): static membrane and cable problems with
// analytic or published references, built through the Model API and solved by load-stepped
// static Newton (StaticNewton under run_time_loop). Suite `Solver`: the fast variants;
// suite `Verification`: the mesh refinements.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "model_builders.hpp"

namespace velum::test {
namespace {

// ---------------------------------------------------------------------------------------------
// B1 Hencky: clamped circular membrane under uniform follower pressure, small-load limit.
//
// A flat membrane has no transverse stiffness, so Newton cannot start from the flat state.
// The static solve starts instead from a domed guess w = w_g (1 - r²/a²) with w_g = a Q^(1/3)
// (the dimensional scale of the answer, about 1.5 times the Hencky deflection): the dome is
// stretched, so the tangent is positive definite, and because the load-deflection curve of a
// membrane is a hardening cubic, Newton from a too-large dome approaches the solution
// monotonically from above. Quarter disc with symmetry planes x = 0 and y = 0.
struct HenckyResult {
  double w0 = 0, reference = 0, error = 0;
  int dofs = 0;
  StaticRun run;
};

// `flat`: from the flat, stress-free sheet itself in `steps` load steps, ramped (the first
// correction borrows a small tension's stiffness: SecondOrderSystem::stiffen_stress_free).
HenckyResult hencky(int n, std::string_view type, bool flat = false, int steps = 1) {
  const double a = 1.0, E = 1e9, t = 1e-3, nu = 0.3, Q = 1e-5;
  const double q = Q * E * t / a;
  Model m;
  NodeCache nodes(m, 1e-9 * a);
  auto conn = quarter_disc(nodes, a, n, type);
  const int b =
      add_membrane(m, type, std::move(conn), PlaneStressLaw::isotropic("film", E, nu), 1000.0, t);
  add_pressure(m, b, q, flat ? add_ramp(m, 1.0) : -1);
  m.fixed.push_back({nodes_where(m, [&](const Vec3& X) { return X.norm() > a * (1 - 1e-9); }),
                     {true, true, true}});
  m.symmetry.push_back(
      {nodes_where(m, [&](const Vec3& X) { return std::abs(X.x()) < 1e-9; }), Vec3::UnitX()});
  m.symmetry.push_back(
      {nodes_where(m, [&](const Vec3& X) { return std::abs(X.y()) < 1e-9; }), Vec3::UnitY()});
  MechanicalSystem sys(m);
  const double wg = a * std::cbrt(Q);
  NodePositions U = NodePositions::Zero(3, m.num_nodes());
  if (!flat)
    for (int k = 0; k < m.num_nodes(); ++k) U(2, k) = wg * (1 - m.X.col(k).squaredNorm() / (a * a));
  State s = state_from(sys, U);
  HenckyResult r;
  r.run = run_static(sys, s, steps);
  const StaticRun& run = r.run;
  EXPECT_TRUE(run.loop.completed) << run.loop.reason;
  r.dofs = sys.size();
  r.w0 = sys.displacements(1.0, s.u)(2, nearest_node(m, Vec3::Zero()));
  r.reference = 0.6534 * a * std::cbrt(Q);
  r.error = percent(r.w0, r.reference);
  fmt::print(
      "B1 w0 error {:.3f}% (quarter disc {} {}x{} per patch, {} dofs, {} Newton its): "
      "w0/a = {:.6f}, Hencky {:.6f}\n",
      r.error, type, n, n, r.dofs, run.loop.iterations, r.w0 / a, r.reference / a);
  return r;
}

TEST(Solver, B1HenckyMembrane) {
  hencky(2, "quad9");
  const HenckyResult r = hencky(4, "quad9");
  EXPECT_LT(r.error, 1.0);
}

// From the flat sheet itself (no domed guess): its tangent has no stiffness normal to the
// sheet, and the first correction borrows a tension's. The same answer as from the dome, in
// one load step or four (a linear ramp); without the borrowed tension it is singular.
TEST(Solver, B1HenckyMembraneFromTheFlatSheet) {
  const HenckyResult dome = hencky(4, "quad9");
  for (const int steps : {1, 4}) {
    const HenckyResult r = hencky(4, "quad9", true, steps);
    // Two converged states, each within the Newton tolerance (measured: 5e-11 and 1.6e-10).
    EXPECT_NEAR(r.w0, dome.w0, 2 * NewtonSettings{}.tolerance * dome.w0) << steps << " step(s)";
    EXPECT_LE(r.run.reports.front().factorizations, 5) << steps << " step(s)";
  }
}

TEST(Verification, B1HenckyMembraneConvergence) {
  std::vector<double> errors;
  for (int n : {2, 4, 8}) errors.push_back(hencky(n, "quad9").error);
  for (int n : {8, 16}) hencky(n, "quad4");
  EXPECT_LT(errors.back(), 1.0);
  EXPECT_LE(errors.back(), errors.front() + 1e-3);  // refinement does not move away
}

// ---------------------------------------------------------------------------------------------
// B2 SVK sphere: equibiaxial inflation of a sphere octant with symmetry planes, follower
// pressure ramped over load steps; p R0/(E t) = (λ² − 1)/((1 − ν) λ).
struct SphereResult {
  double lambda = 0, spread = 0, error = 0;
  StaticRun run;
};

double sphere_pressure(double lambda, double nu) {
  return (lambda * lambda - 1) / ((1 - nu) * lambda);
}

SphereResult sphere(double lambda, int n, std::string_view type, int steps,
                    const NewtonSettings& newton = {}) {
  const double R0 = 1.0, E = 1e9, t = 1e-3, nu = 0.3;
  const double p = sphere_pressure(lambda, nu) * E * t / R0;
  Model m;
  NodeCache nodes(m, 1e-9 * R0);
  auto conn = sphere_octant(nodes, R0, n, type);
  const int b =
      add_membrane(m, type, std::move(conn), PlaneStressLaw::isotropic("skin", E, nu), 1000.0, t);
  add_pressure(m, b, p, add_ramp(m, 1.0));
  for (int c = 0; c < 3; ++c)
    m.symmetry.push_back(
        {nodes_where(m, [&](const Vec3& X) { return std::abs(X[c]) < 1e-9; }), Vec3::Unit(c)});
  MechanicalSystem sys(m);
  State s = state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  SphereResult r;
  r.run = run_static(sys, s, steps, newton);
  EXPECT_TRUE(r.run.loop.completed) << r.run.loop.reason;
  const NodePositions x = m.X + sys.displacements(1.0, s.u);
  double lo = 1e300, hi = 0, sum = 0;
  for (int k = 0; k < m.num_nodes(); ++k) {
    const double l = x.col(k).norm() / m.X.col(k).norm();
    lo = std::min(lo, l), hi = std::max(hi, l), sum += l;
  }
  r.lambda = sum / m.num_nodes();
  r.spread = hi - lo;
  r.error = percent(sphere_pressure(r.lambda, nu), sphere_pressure(lambda, nu));
  fmt::print(
      "B2 p R0/(E t) error {:.4f}% at lambda {} (octant {} {}x{} per patch, {} load "
      "steps): measured lambda {:.7f} (spread {:.1e})\n",
      r.error, lambda, type, n, n, steps, r.lambda, r.spread);
  return r;
}

// Observed rates log(r[k+1]/r[k]) / log(r[k]/r[k-1]) of a residual sequence, kept while the
// residual is well above round-off (1e-10 of the first).
std::vector<double> convergence_rates(const std::vector<double>& r) {
  std::vector<double> q;
  for (size_t k = 1; k + 1 < r.size(); ++k)
    if (r[k + 1] > 1e-10 * r[0]) q.push_back(std::log(r[k + 1] / r[k]) / std::log(r[k] / r[k - 1]));
  return q;
}

void check_quadratic(const SphereResult& r) {
  const auto& res = r.run.reports.back().residuals;
  std::string seq;
  for (double v : res) seq += fmt::format(" {:.3e}", v);
  const auto q = convergence_rates(res);
  std::string rates;
  for (double v : q) rates += fmt::format(" {:.2f}", v);
  fmt::print("B2 Newton residuals of the last load step:{}\nB2 observed rates:{}\n", seq, rates);
  ASSERT_FALSE(q.empty());
  EXPECT_GT(q.back(), 1.8);
}

// Quadratic convergence checks the tangent, so every correction gets a fresh one (no chord
// steps, whose convergence is linear by design).
TEST(Solver, B2SvkSphere) {
  NewtonSettings ns;
  ns.tolerance = 1e-12;
  ns.abs_residual = 0;
  ns.reuse_tangent = false;
  const SphereResult a = sphere(1.1, 4, "quad9", 2, ns);
  EXPECT_LT(a.error, 0.2);
  const SphereResult b = sphere(1.5, 4, "quad9", 5, ns);
  EXPECT_LT(b.error, 0.2);
  check_quadratic(b);
}

TEST(Verification, B2SvkSphereRefined) {
  NewtonSettings ns;
  ns.tolerance = 1e-12;
  ns.abs_residual = 0;
  ns.reuse_tangent = false;
  for (const char* type : {"quad9", "quad4", "tri3"}) {
    const int n = std::string_view(type) == "quad9" ? 8 : 16;
    EXPECT_LT(sphere(1.1, n, type, 2, ns).error, 0.2) << type;
    const SphereResult b = sphere(1.5, n, type, 5, ns);
    EXPECT_LT(b.error, 0.2) << type;
    check_quadratic(b);
  }
}

// ---------------------------------------------------------------------------------------------
// B3 Heavy cable (code_aster SSNL114): span = unstressed length, gravity ramped over 4 load
// steps. The straight cable has no transverse stiffness, so the static solve starts from a
// parabolic sag guess of 10 m (larger than the answer; the hardening cubic response makes
// Newton approach from above).
double heavy_cable(int n, std::string_view type) {
  const double L = 325, A = 2.2783e-4, E = 5.70e10, rho = 2844.23, g = 9.81;
  Model m;
  NodeCache nodes(m, 1e-9 * L);
  std::vector<int> chain;
  auto conn = cable_chain(nodes, Vec3::Zero(), Vec3(L, 0, 0), n, type, chain);
  add_cable(m, type, std::move(conn), CableLaw{E, false}, rho, A);
  m.fixed.push_back({{chain.front(), chain.back()}, {true, true, true}});
  m.fixed.push_back({chain, {false, true, false}});  // the cable hangs in the x-z plane
  m.gravity.push_back({Vec3(0, 0, -g), add_ramp(m, 1.0)});
  MechanicalSystem sys(m);
  NodePositions U = NodePositions::Zero(3, m.num_nodes());
  const double guess = 10.0;
  for (int k = 0; k < m.num_nodes(); ++k) {
    const double x = m.X(0, k);
    U(2, k) = -4 * guess * x * (L - x) / (L * L);
  }
  State s = state_from(sys, U);
  const StaticRun run = run_static(sys, s, 4);
  EXPECT_TRUE(run.loop.completed) << run.loop.reason;
  const double sag = -sys.displacements(1.0, s.u)(2, nearest_node(m, Vec3(0.5 * L, 0, 0)));
  const double err = percent(sag, 6.352);
  fmt::print(
      "B3 midspan sag error {:.4f}% ({} x {}, {} Newton its): sag {:.5f} m, reference "
      "6.352 m\n",
      err, n, type, run.loop.iterations, sag);
  return err;
}

TEST(Solver, B3HeavyCable) {
  EXPECT_LT(heavy_cable(20, "cable3"), 0.1);
}

TEST(Verification, B3HeavyCableRefined) {
  EXPECT_LT(heavy_cable(100, "cable3"), 0.1);
  EXPECT_LT(heavy_cable(200, "cable2"), 0.1);
}

// ---------------------------------------------------------------------------------------------
// B4 Cable slackening (after code_aster SSNL105). Our reading: unit square 1 (0,0), 2 (0,1),
// 3 (1,1), 4 (1,0) in the x-y plane; the four sides are bars (trusses carrying compression),
// the diagonals 1-3 and 2-4 are tension-only cables, all with E A = 2e7 N; node 1 pinned,
// node 4 on a roller (y fixed), z fixed everywhere; F_x = 1000 N at node 3. With cable 2-4
// slack the truss is statically determinate: cable 1-3 carries 1000 √2 N, bar 3-4 1000 N
// (compression), the other bars and cable 2-4 nothing. The first Newton iteration (every
// member taut at zero strain) puts cable 2-4 in compression; it then goes slack.
TEST(Solver, B4CableSlackening) {
  Model m;
  const int n1 = m.add_node(1, Vec3(0, 0, 0)), n2 = m.add_node(2, Vec3(0, 1, 0)),
            n3 = m.add_node(3, Vec3(1, 1, 0)), n4 = m.add_node(4, Vec3(1, 0, 0));
  const double E = 2e11, A = 1e-4;
  const int bars =
      add_cable(m, "cable2", {n1, n2, n2, n3, n3, n4, n4, n1}, CableLaw{E, true}, 0.0, A);
  const int cables = add_cable(m, "cable2", {n1, n3, n2, n4}, CableLaw{E, false}, 0.0, A);
  m.fixed.push_back({{n1}, {true, true, true}});
  m.fixed.push_back({{n4}, {false, true, true}});
  m.fixed.push_back({{n2, n3}, {false, false, true}});
  m.point_loads.push_back({{n3}, Vec3(1000, 0, 0), -1});
  MechanicalSystem sys(m);
  State s = state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  NewtonSettings ns;
  ns.tolerance = 1e-12;
  const StaticRun run = run_static(sys, s, 1, ns);
  ASSERT_TRUE(run.loop.completed) << run.loop.reason;
  const NodePositions x = m.X + sys.displacements(1.0, s.u);
  const double loaded = m.blocks[cables]->output(0, x).cable_force;
  const double other = m.blocks[cables]->output(1, x).cable_force;
  const double bar34 = m.blocks[bars]->output(2, x).cable_force;
  const double e_loaded = percent(loaded, 1000 * std::sqrt(2.0)), e_bar = percent(-bar34, 1000);
  fmt::print(
      "B4 loaded cable {:.3f} N (error {:.4f}%), bar 3-4 {:.3f} N (error {:.4f}%), other "
      "cable {:.3e} N ({} Newton its, residuals",
      loaded, e_loaded, bar34, e_bar, other, run.loop.iterations);
  for (double r : run.reports.back().residuals) fmt::print(" {:.2e}", r);
  fmt::print(")\n");
  EXPECT_LT(e_loaded, 0.05);
  EXPECT_LT(e_bar, 0.05);
  EXPECT_LE(std::abs(other), 1e-6);
  EXPECT_LE((x.col(n4) - x.col(n2)).norm(), std::sqrt(2.0) * (1 + 1e-12));  // not stretched
}

// ---------------------------------------------------------------------------------------------
// B5 TL cable under a hanging load: one element, top fixed, load F at the bottom node;
// F/(E A) = λ (λ² − 1)/2 (true force = 2nd PK force times stretch).
double hanging_cable(std::string_view type, double ratio) {
  const double L = 2.0, E = 1e9, A = 1e-4;
  Model m;
  NodeCache nodes(m, 1e-9);
  std::vector<int> chain;
  auto conn = cable_chain(nodes, Vec3::Zero(), Vec3(0, 0, -L), 1, type, chain);
  add_cable(m, type, std::move(conn), CableLaw{E, false}, 0.0, A);
  m.fixed.push_back({{chain.front()}, {true, true, true}});
  m.fixed.push_back({chain, {true, true, false}});
  m.point_loads.push_back({{chain.back()}, Vec3(0, 0, -ratio * E * A), add_ramp(m, 1.0)});
  MechanicalSystem sys(m);
  State s = state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  NewtonSettings ns;
  ns.tolerance = 1e-13;
  ns.abs_residual = 0;
  const StaticRun run = run_static(sys, s, 2, ns);
  EXPECT_TRUE(run.loop.completed) << run.loop.reason;
  const double lambda = (L - sys.displacements(1.0, s.u)(2, chain.back())) / L;
  // Reference: the real root of λ³ − λ − 2 ratio = 0 by Newton.
  double ref = 1.0 + ratio;
  for (int i = 0; i < 50; ++i) ref -= (ref * ref * ref - ref - 2 * ratio) / (3 * ref * ref - 1);
  fmt::print(
      "B5 lambda error {:.2e} ({}, F/EA = {}, {} Newton its): lambda {:.10f}, exact "
      "{:.10f}\n",
      std::abs(lambda - ref), type, ratio, run.loop.iterations, lambda, ref);
  return std::abs(lambda - ref);
}

TEST(Solver, B5HangingCable) {
  EXPECT_NEAR(
      1.08803391,
      [] {
        double l = 1.1;
        for (int i = 0; i < 50; ++i) l -= (l * l * l - l - 0.2) / (3 * l * l - 1);
        return l;
      }(),
      5e-9);
  EXPECT_LT(hanging_cable("cable2", 0.1), 1e-9);
  EXPECT_LT(hanging_cable("cable3", 0.1), 1e-9);
}

}  // namespace
}  // namespace velum::test
