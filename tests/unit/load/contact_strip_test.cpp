// VERIFICATION.md F1: a prestressed strip over a fixed frictionless cylinder, pulled at both
// ends by its tension N along the tangents at ±θ: the contact pressure in the wrapped zone is
// N / R (R to the strip's middle surface) and the force on the cylinder the vector sum of the
// end tensions, 2 N w sin θ downwards. Static Newton with the multipliers updated at each
// accepted step; the residuals of the last step show Newton's rate once the active set holds.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "../../verification/model_builders.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

constexpr double kR = 0.5, kT = 1e-3, kN = 1000.0, kW = 0.1, kTheta = 0.5236, kStraight = 0.3;

// The strip over the drum; with friction mu the right end is pulled along its tangent by
// `pull` (a ramp over t in [0, 1]) instead of loaded, so that the strip slides.
std::unique_ptr<Model> strip_on_cylinder(int along, double mu = 0, double pull = 0) {
  auto m = std::make_unique<Model>();
  test::NodeCache nodes(*m, 1e-9);
  std::vector<int> conn;
  const double Rm = kR + 0.5 * kT;  // the middle surface, one contact thickness off the drum
  const double arc = Rm * kTheta, half = arc + kStraight;
  test::mesh_patch(
      nodes,
      [&](double u, double v) {
        const double s = (2 * u - 1) * half, y = kW * v;
        if (std::abs(s) <= arc) return Vec3(Rm * std::sin(s / Rm), y, Rm * std::cos(s / Rm));
        const double sg = s > 0 ? 1 : -1, phi = sg * kTheta, d = std::abs(s) - arc;
        return Vec3(Rm * std::sin(phi) + d * sg * std::cos(phi), y,
                    Rm * std::cos(phi) - d * std::sin(kTheta));
      },
      along, 2, "quad4", conn);
  const double S = kN / kT;  // isotropic 2nd PK prestress: tension N in every direction
  test::add_membrane(*m, "quad4", std::move(conn),
                     SheetLaw(PlaneStressLaw::isotropic("iso", 1e9, 0.3)).with_prestress({S, S, 0}),
                     1000.0, kT);
  std::vector<int> all(static_cast<size_t>(m->num_nodes()));
  for (int n = 0; n < m->num_nodes(); ++n) all[static_cast<size_t>(n)] = n;
  m->fixed.push_back({all, {false, true, false}});
  if (mu == 0) m->fixed.push_back({{test::nearest_node(*m, Vec3(0, 0, Rm))}, {true, false, false}});
  // The end tensions, shared as a linear edge's consistent loads (w/4, w/2, w/4).
  for (int side : {-1, 1}) {
    const Vec3 dir(side * std::cos(kTheta), 0, -std::sin(kTheta));
    const double Rm2 = kR + 0.5 * kT;
    const double x = side * (Rm2 * std::sin(kTheta) + kStraight * std::cos(kTheta));
    const double z = Rm2 * std::cos(kTheta) - kStraight * std::sin(kTheta);
    std::vector<int> end;
    for (int j = 0; j < 3; ++j) end.push_back(test::nearest_node(*m, Vec3(x, 0.5 * kW * j, z)));
    if (mu > 0 && side > 0) {
      m->prescribed.push_back({end, pull * dir, test::add_ramp(*m, 1.0)});
      continue;
    }
    for (int j = 0; j < 3; ++j)
      m->point_loads.push_back(
          {{end[static_cast<size_t>(j)]}, kN * kW * (j == 1 ? 0.5 : 0.25) * dir, -1});
  }
  ContactLoad cl;
  cl.body.name = "drum";
  cl.body.shape = RigidBody::Shape::kCylinder;
  cl.body.point = Vec3::Zero();
  cl.body.direction = Vec3::UnitY();
  cl.body.radius = kR;
  cl.friction = mu;
  cl.parts.push_back({0, {}});
  for (int e = 0; e < m->blocks[0]->size(); ++e) cl.parts[0].elements.push_back(e);
  m->loads.add(make_load(cl));
  for (auto& l : m->loads) l->set_up(*m);
  return m;
}

TEST(Contact, StripOverCylinderCarriesTensionOverRadius) {
  auto m = strip_on_cylinder(48);
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1, loop.step = 0.2;  // the same load, the multipliers move on
  std::vector<StepReport> reports;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        reports.push_back(*st.report);
        return true;
      });
  ASSERT_TRUE(r.completed);
  std::cout << "Newton residuals of the last step:";
  for (double v : reports.back().residuals) std::cout << " " << v;
  std::cout << "\n";

  const NodePositions x = m->X + sys.displacements(1, s.u);
  const double Rm = kR + 0.5 * kT;
  // The force on the drum: the sum of the end tensions.
  const double Fz = *sys.loads().back()->quantity_at("contact_force:contact=0:2", 1, x);
  const double Fx = *sys.loads().back()->quantity_at("contact_force:body=drum:0", 1, x);
  const double exact = -2 * kN * kW * std::sin(kTheta);
  std::cout << "drum force z " << Fz << " exact " << exact << " (" << test::percent(Fz, exact)
            << "%), x " << Fx << "\n";
  EXPECT_LT(test::percent(Fz, exact), 1.0);
  EXPECT_LT(std::abs(Fx), 1e-3 * std::abs(exact));
  // The pressure inside the wrapped zone (an element away from its ends), and the gaps.
  const std::vector<double> q = sys.load_node_field("contact_pressure", 1, x);
  const std::vector<double> g = sys.load_node_field("contact_gap", 1, x);
  double worst = 0, least_gap = 1;
  int inside = 0;
  for (int n = 0; n < m->num_nodes(); ++n) {
    least_gap = std::min(least_gap, g[static_cast<size_t>(n)]);
    const double phi = std::atan2(m->X(0, n), m->X(2, n));
    if (std::abs(phi) > kTheta - 0.05 || m->X(1, n) < 1e-9 || m->X(1, n) > kW - 1e-9) continue;
    ++inside;
    const double e = test::percent(q[static_cast<size_t>(n)], kN / Rm);
    worst = std::isnan(e) ? 1e9 : std::max(worst, e);
  }
  const double h = 2 * (Rm * kTheta + kStraight) / 48;
  std::cout << "pressure N/R " << kN / Rm << ": worst error " << worst << "% over " << inside
            << " nodes; least gap " << least_gap << " (tolerance " << -1e-3 * h << ")\n";
  EXPECT_GT(inside, 5);
  EXPECT_LT(worst, 2.0);
  EXPECT_GT(least_gap, -std::max(0.01 * kT, 1e-3 * h));
  // Newton converges in few iterations once the active set holds (the later steps).
  EXPECT_LE(reports.back().iterations, 4);
  // The contact area: the wrapped zone w Rm 2θ, within an element length of strip (the area
  // is the nodes' that touch); the status: slip (frictionless) in the wrap, open on the
  // straight parts.
  const double area = *sys.loads().back()->quantity_at("contact_area:contact=0", 1, x);
  const double wrapped = kW * Rm * 2 * kTheta;
  std::cout << "contact area " << area << " wrapped zone " << wrapped << " ("
            << test::percent(area, wrapped) << "%)\n";
  EXPECT_LT(std::abs(area - wrapped), kW * h);
  EXPECT_EQ(*sys.loads().back()->quantity_at("contact_area:body=drum", 1, x), area);
  const std::vector<double> st = sys.load_node_field("contact_status", 1, x);
  int slip = 0, open = 0, wrong = 0;
  for (int n = 0; n < m->num_nodes(); ++n) {
    const double phi = std::atan2(m->X(0, n), m->X(2, n)), v = st[static_cast<size_t>(n)];
    if (std::abs(phi) < kTheta - 0.05) (v == 2 ? slip : wrong)++;
    if (std::abs(phi) > kTheta + 0.05) (v == 0 ? open : wrong)++;
  }
  EXPECT_GT(slip, 5);
  EXPECT_GT(open, 5);
  EXPECT_EQ(wrong, 0);
}

// F2: the capstan. The left end held by its tension N, the right end pulled on so that the
// strip slides over the drum: the right end's force is N e^(μ 2θ).
// The pulled end's tension over the held end's after a pull `pull` along the strip.
// `status`: how many nodes of the wrapped zone are open, stick and slip at the end.
double capstan_ratio(double mu, double pull, std::array<int, 3>* status = nullptr) {
  auto m = strip_on_cylinder(48, mu, pull);
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1, loop.step = 0.1;
  std::vector<StepReport> reports;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        reports.push_back(*st.report);
        return true;
      });
  EXPECT_TRUE(r.completed) << r.reason;
  if (!r.completed) return std::nan("");
  std::cout << "Newton residuals of the last step:";
  for (double v : reports.back().residuals) std::cout << " " << v;
  std::cout << "\n";
  // The pulled end's force: its nodes' internal forces along the strip.
  const NodePositions x = m->X + sys.displacements(1, s.u);
  NodePositions Fint;
  sys.assembler().internal(x, Fint, nullptr);
  const Vec3 dir(std::cos(kTheta), 0, -std::sin(kTheta));
  double T2 = 0;
  for (int n : m->prescribed[0].nodes) T2 += Fint.col(n).dot(dir);
  T2 /= kW;
  if (status) {
    const std::vector<double> st = sys.load_node_field("contact_status", 1, x);
    status->fill(0);
    for (int n = 0; n < m->num_nodes(); ++n)
      if (std::abs(std::atan2(m->X(0, n), m->X(2, n))) < kTheta - 0.05)
        ++(*status)[static_cast<size_t>(st[static_cast<size_t>(n)])];
  }
  return T2 / kN;
}

TEST(Contact, CapstanEndForcesInTheRatioOfFriction) {
  const double mu = 0.3;
  std::array<int, 3> status{};
  const double ratio = capstan_ratio(mu, 0.01, &status), exact = std::exp(mu * 2 * kTheta);
  std::cout << "capstan: T2/T1 " << ratio << " exact " << exact << " ("
            << test::percent(ratio, exact) << "%); wrapped nodes open/stick/slip " << status[0]
            << "/" << status[1] << "/" << status[2] << "\n";
  EXPECT_LT(test::percent(ratio, exact), 1.5);
  // Sliding: every node of the wrap slips.
  EXPECT_EQ(status[0] + status[1], 0);
  EXPECT_GT(status[2], 5);
}

// Below the capstan ratio the strip sticks: a small pull raises the pulled end's tension
// above the held end's (friction carries the difference: without it there would be no
// equilibrium) but stays below N e^(μ 2θ).
TEST(Contact, CapstanSticksBelowTheRatioOfFriction) {
  const double mu = 0.3;
  std::array<int, 3> status{};
  const double ratio = capstan_ratio(mu, 1e-5, &status), exact = std::exp(mu * 2 * kTheta);
  std::cout << "capstan, sticking: T2/T1 " << ratio << " (slip at " << exact
            << "); wrapped nodes open/stick/slip " << status[0] << "/" << status[1] << "/"
            << status[2] << "\n";
  EXPECT_EQ(status[0], 0);
  EXPECT_GT(status[1], 5);  // the most of the wrap sticks
  EXPECT_GT(ratio, 1.002);
  EXPECT_LT(ratio, 0.99 * exact);
}

}  // namespace
}  // namespace velum
