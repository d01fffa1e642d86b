// VERIFICATION.md F3: a gas cushion (a square sheet over the plane of its held edges,
// enclosing gas) pressed by a rigid plate moving down: in the flat patch under the plate the
// contact pressure equals the gas's gauge pressure, and the plate force is its integral.
#include <gtest/gtest.h>

#include <iostream>
#include <numbers>

#include "../../verification/model_builders.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/model/gas_chamber.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

constexpr double kA = 0.5, kBump = 0.1, kGauge = 2000.0, kPlateEnd = 0.06;

std::unique_ptr<Model> cushion_under_plate() {
  auto m = std::make_unique<Model>();
  test::NodeCache nodes(*m, 1e-9);
  std::vector<int> conn;
  const double pi = std::numbers::pi;
  test::mesh_patch(
      nodes,
      [&](double u, double v) {
        const double x = kA * (2 * u - 1), y = kA * (2 * v - 1);
        return Vec3(x, y, kBump * std::cos(pi * x / (2 * kA)) * std::cos(pi * y / (2 * kA)));
      },
      12, 12, "quad4", conn);
  test::add_membrane(
      *m, "quad4", std::move(conn),
      SheetLaw(PlaneStressLaw::isotropic("iso", 1e8, 0.3)).with_prestress({1e5, 1e5, 0}), 1000.0,
      1e-3);
  m->fixed.push_back({test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.z()) < 1e-12; }),
                      {true, true, true}});
  GasLoad gas;
  gas.parts.push_back({0, {}});
  for (int e = 0; e < m->blocks[0]->size(); ++e) gas.parts[0].elements.push_back(e);
  gas.initial_pressure = 1e5 + kGauge, gas.ambient = 1e5, gas.gamma = 1.0;
  m->gases.push_back(gas);
  ContactLoad cl;
  cl.body.name = "plate";
  cl.body.shape = RigidBody::Shape::kPlane;
  cl.body.point = Vec3(0, 0, 0.2);
  cl.body.direction = -Vec3::UnitZ();  // solid above
  cl.body.displacement = Vec3(0, 0, kPlateEnd - 0.2);
  cl.body.function = test::add_ramp(*m, 1.0);
  cl.parts.push_back({0, gas.parts[0].elements});
  m->loads.add(make_load(cl));
  for (auto& l : m->loads) l->set_up(*m);
  return m;
}

TEST(Contact, GasCushionPressedByPlateCarriesGaugePressure) {
  auto m = cushion_under_plate();
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1.2, loop.step = 0.1;  // the plate stops at t = 1: two more steps
  std::vector<StepReport> reports;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        reports.push_back(*st.report);
        return true;
      });
  ASSERT_TRUE(r.completed) << r.reason;
  std::cout << "Newton residuals of the last step:";
  for (double v : reports.back().residuals) std::cout << " " << v;
  std::cout << "\n";

  const double t = loop.t_end;
  const NodePositions x = m->X + sys.displacements(t, s.u);
  const double gauge = *sys.load_quantity_at("gas_pressure", 0, t, x) - 1e5;
  const LoadTerm& contact = *sys.loads().back();
  const double F = *contact.quantity_at("contact_force:body=plate:2", t, x);
  const std::vector<double> q = sys.load_node_field("contact_pressure", t, x);
  // The patch: the nodes pressed; its inside: those whose neighbours one cell away are too.
  const double h = 2 * kA / 12;
  std::vector<int> pressed;
  for (int n = 0; n < m->num_nodes(); ++n)
    if (q[static_cast<size_t>(n)] > 0) pressed.push_back(n);
  double worst = 0, integral = 0;
  int inside = 0;
  for (int n : pressed) {
    int near = 0;
    for (int o : pressed) near += (m->X.col(o) - m->X.col(n)).head<2>().norm() < 1.5 * h;
    if (near < 9) continue;
    ++inside;
    worst = std::max(worst, test::percent(q[static_cast<size_t>(n)], gauge));
  }
  // The integral of the contact pressure: each node's pressure times its area (the forces of
  // a unit follower pressure on the sheet).
  NodePositions unit = NodePositions::Zero(3, m->num_nodes());
  const SurfaceBlock& b = *m->blocks[0]->surface();
  std::vector<double> f(static_cast<size_t>(b.dofs_per_element()));
  for (int e = 0; e < b.size(); ++e) {
    std::fill(f.begin(), f.end(), 0.0);
    b.pressure(std::span<const int>(&e, 1), x, 1.0, f.data(), nullptr);
    const auto en = b.nodes(e);
    for (size_t a = 0; a < en.size(); ++a) unit.col(en[a]) += Eigen::Map<const Vec3>(&f[3 * a]);
  }
  for (int n : pressed) integral += q[static_cast<size_t>(n)] * unit(2, n);
  std::cout << "gauge " << gauge << " Pa; patch of " << pressed.size() << " nodes, " << inside
            << " inside: worst error " << worst << "%; plate force " << F << " N, integral "
            << integral << " N (" << test::percent(F, integral) << "%)\n";
  EXPECT_GT(inside, 8);
  EXPECT_LT(worst, 3.0);
  EXPECT_LT(test::percent(F, integral), 2.0);
  EXPECT_GT(gauge, 0.5 * kGauge);  // the cushion rose before the plate reached it: V grew
}

}  // namespace
}  // namespace velum
