// A free wedge that rotates (an inertia, docs/contact.md "Rotation") against the anisotropic
// strip of the edge tests, its ridge across the strip's middle element, with friction on the
// edge pairs. Within a step the orientation depends on the committed state only, so the term's
// matrix (the body's translation coupled through the low-rank columns) is the exact derivative
// of its forces: checked against central differences at a turned orientation mid-step, in stick
// and slip; and in implicit dynamics (generalized-α, ρ∞ = 0.5) with the wedge spinning at
// 2 rad/s and pushed up into the strip away from its centre of mass, Newton squares its residual
// in every step with the contact active.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"
#include "wedge_strip.hpp"

namespace velum {
namespace {

// The strip and a free spinning wedge (its ridge at `top`, 0.5 kg, principal inertias 2, 1,
// 2.5 g m² times `scale`, its centre of mass 1 cm and 2 cm off the ridge's middle): the body's
// node.
int add_spinning_wedge(Model& m, double top, double mu, const Vec3& omega, double scale = 1) {
  RigidBody b = test::wedge(top);
  b.point = Vec3(0.01, 0.02, top - 0.02);
  b.inertia = scale * Vec3(2e-3, 1e-3, 2.5e-3).asDiagonal();
  b.angular_velocity = omega;
  const int node = m.add_node(1000, b.point);
  m.masses.push_back({node, 0.5});
  ContactLoad cl;
  cl.body = b;
  cl.edges = true;
  cl.friction = mu;
  cl.body_node = node;
  cl.parts.push_back({0, {0, 1, 2}});
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  return node;
}

TEST(RigidEdgeRotation, TermMatrixMatchesFiniteDifferencesTurnedMidStep) {
  for (const bool slip : {false, true}) {
    auto m = test::strip(true);
    // Heavy enough for the pairs' moment to turn it by little besides its spin.
    const int node = add_spinning_wedge(*m, 0.2e-3, 0.3, Vec3(0.2, 0.1, 3.0), 1e3);
    MechanicalSystem sys(*m);
    const int n = sys.size();
    const VecX zero = VecX::Zero(n);
    // The pairs anchor at the start; an accepted step turns the wedge (its spin and the
    // pairs' moment); the term is checked within the next step.
    sys.start_loads(0, zero, zero);
    sys.accept(0.01, zero, zero);
    const double t = 0.02;
    NodePositions shift = NodePositions::Zero(3, m->num_nodes());
    if (slip)
      for (int i = 0; i < m->num_nodes(); ++i)
        if (i != node && std::abs(m->X(0, i)) < 0.2) shift.col(i) = Vec3(0, 1e-3, 0);
    VecX u;
    sys.dofs().gather(shift, u);
    std::srand(7);
    u += 1e-5 * VecX::Random(n);
    MatX J;
    const VecX f = term_forces(sys, 0, u, &J, t);
    ASSERT_GT(f.norm(), 0);
    const double err = term_matrix_error(sys, 0, u, J, 1e-9, t);
    const NodePositions x = m->X + sys.displacements(t, u);
    const double turned = *sys.loads()[0]->quantity_at("rigid_rotation:wedge:3", t, x);
    std::cout << "spinning free wedge, friction 0.3, " << (slip ? "slip" : "stick")
              << ", mid-step: term matrix against central differences " << err << " (turned by "
              << turned << " rad)\n";
    EXPECT_LT(err, 1e-6);
    EXPECT_GT(turned, 0.02);
    NodePositions Fn = NodePositions::Zero(3, m->num_nodes());
    sys.dofs().scatter(f, Fn);
    EXPECT_LT(Fn.rowwise().sum().norm(), 1e-9 * f.norm());
  }
}

TEST(RigidEdgeRotation, NewtonIsQuadraticWithASpinningOffCentreWedgeInContact) {
  auto m = test::strip(true);
  const int node = add_spinning_wedge(*m, -0.5e-3, 0.3, Vec3(0, 0, 2.0));
  // Pushed up into the strip by 5 N (ramped over 5 ms), off its centre of mass.
  m->point_loads.push_back({{node}, Vec3(0, 0, 5.0), test::add_ramp(*m, 0.005)});
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  NodePositions V = NodePositions::Zero(3, m->num_nodes());
  V(2, node) = 0.005;  // up into the strip at 5 mm/s
  sys.dofs().gather(V, s.v);
  sys.start_loads(0, s.u, s.v);
  auto integrator = GeneralizedAlpha::chung_hulbert(0.5);
  integrator->newton.reuse_tangent = false;  // pure Newton: the residuals show the tangent
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 0.02, loop.step = 2e-4;
  std::vector<std::vector<double>> res;
  std::vector<double> force;
  Vec3 omega = Vec3::Zero();
  const TimeLoopResult r = run_time_loop(
      sys, *integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        const NodePositions x = m->X + sys.displacements(st.t, c.u);
        res.push_back(st.report->residuals);
        force.push_back(*sys.loads().back()->quantity_at("contact_force:body=wedge:2", st.t, x));
        for (int k = 0; k < 3; ++k)
          omega[k] = *sys.loads().back()->quantity_at(
              "rigid_angular_velocity:wedge:" + std::to_string(k), st.t, x);
        return true;
      });
  ASSERT_TRUE(r.completed) << r.reason;
  int active = 0;
  std::cout << "spinning wedge pushed off its centre, Newton residuals of the steps in contact "
               "(force on the wedge):\n";
  for (size_t k = 0; k < res.size(); ++k) {
    if (force[k] == 0 || k == 0 || force[k - 1] == 0) continue;  // settled steps in contact
    ++active;
    std::cout << " (" << force[k] << " N)";
    for (double v : res[k]) std::cout << " " << v;
    std::cout << "\n";
    const std::vector<double>& q = res[k];
    EXPECT_LE(q.size(), 5u) << "step " << k;
    for (size_t i = 1; i + 1 < q.size(); ++i) {
      const double r1 = q[i] / q[0], r0 = q[i - 1] / q[0];
      EXPECT_LT(r1, 100 * r0 * r0 + 1e-11) << "step " << k << " iteration " << i;
    }
  }
  std::cout << "angular velocity at the end " << omega.transpose()
            << " rad/s (spun at 2 about z)\n";
  EXPECT_GT(active, 50);  // of 100 steps
  // Pushed off its centre of mass, it turns about x and y too.
  EXPECT_GT(std::hypot(omega.x(), omega.y()), 1e-3);
}

}  // namespace
}  // namespace velum
