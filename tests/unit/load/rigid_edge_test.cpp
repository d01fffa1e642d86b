// Edge contact with a rigid mesh (contact `edges: true` with a mesh body, docs/contact.md
// "Rigid meshes"): a wedge's ridge pushed up into a strip one element wide, across an element
// and between its nodes. Node to surface alone lets the ridge through the strip; with the
// strip's sides against the mesh's sharp edges the strip rests on the ridge. The term's matrix
// (K and, for a free wedge, its low-rank coupling with the body's node) against central
// differences of its forces, on an anisotropic sheet.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"
#include "wedge_strip.hpp"

namespace velum {
namespace {

using test::kT;
using test::strip;
using test::wedge;

void add_contact(Model& m, const RigidBody& body, bool edges, int body_node = -1) {
  ContactLoad cl;
  cl.body = body;
  cl.edges = edges;
  cl.body_node = body_node;
  cl.parts.push_back({0, {0, 1, 2}});
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
}

TEST(RigidEdge, WedgeHasOneRidgeAcrossTheStrip) {
  const RigidBody b = wedge(0.0);
  int ridges = 0;
  for (const auto& e : b.mesh->sharp_edges()) {
    const Vec3 d =
        b.mesh->vertices()[static_cast<size_t>(e.b)] - b.mesh->vertices()[static_cast<size_t>(e.a)];
    // The ridge: along y at the top, its outward direction up.
    if (std::abs(d.x()) < 1e-12 && std::abs(d.z()) < 1e-12 && e.out.z() > 0.99) ++ridges;
  }
  EXPECT_EQ(ridges, 1);
  // The prism's nine edges are sharp; the faces' diagonals are not.
  EXPECT_EQ(b.mesh->sharp_edges().size(), 9u);
}

TEST(RigidEdge, TermMatrixMatchesFiniteDifferences) {
  for (const bool free : {false, true}) {
    auto m = strip(true);
    // The ridge 0.3 mm into the strip's contact distance, turned and moved a little by its
    // motion (held body), or a free body with its node and mass.
    RigidBody b = wedge(0.2e-3);
    int node = -1;
    if (free) {
      node = m->add_node(1000, b.point);
      m->masses.push_back({node, 5.0});
    } else {
      b.rotation = Vec3(0.01, 0.005, 0.3), b.displacement = Vec3(0.002, 0.001, 0.0);
      b.pivot = Vec3(0, 0, 0.2e-3);
    }
    add_contact(*m, b, true, node);
    MechanicalSystem sys(*m);
    const int n = sys.size();
    std::srand(3);
    const VecX u = 1e-5 * VecX::Random(n);
    sys.start_loads(0, u, VecX::Zero(n));
    MatX J;
    const VecX f = term_forces(sys, 0, u, &J);
    ASSERT_GT(f.norm(), 0);
    const double err = term_matrix_error(sys, 0, u, J, 1e-9);
    std::cout << "wedge ridge " << (free ? "(free body)" : "(moved, turned)")
              << ": term matrix against central differences " << err << " (" << n
              << " equations)\n";
    EXPECT_LT(err, 1e-6);
    if (free) {  // the body takes the opposite of the strip's forces
      NodePositions Fn = NodePositions::Zero(3, m->num_nodes());
      sys.dofs().scatter(f, Fn);
      EXPECT_LT(Fn.rowwise().sum().norm(), 1e-9 * f.norm());
    }
  }
}

// The wedge moved up 6 mm (its ridge from 2 mm below the strip to 4 mm above it) in ten static
// steps; returns the strip's height over the ridge where its sides cross it.
double height_over_ridge(bool edges, std::vector<std::vector<double>>* residuals = nullptr,
                         double* balance = nullptr) {
  auto m = strip(true);
  RigidBody b = wedge(-0.002);
  b.displacement = Vec3(0, 0, 0.006);
  b.function = test::add_ramp(*m, 1.0);
  add_contact(*m, b, edges);
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  integrator.newton.reuse_tangent = false;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1, loop.step = 0.1;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        if (residuals) residuals->push_back(st.report->residuals);
        return true;
      });
  EXPECT_TRUE(r.completed) << r.reason;
  const NodePositions x = m->X + sys.displacements(1, s.u);
  if (balance) {  // the force on the wedge (history) against the strip's held ends' reactions
    const double F = *sys.loads()[0]->quantity_at("contact_force:contact=0:2", 1, x);
    const NodePositions R = sys.reactions(1, s.u, s.v);
    *balance = (R.row(2).sum() - F) / F;
    std::cout << "force on the wedge " << F << " N, the held ends' reactions " << R.row(2).sum()
              << " N\n";
  }
  // The middle element's sides are straight between its inner nodes at x = ±0.1.
  const int a = test::nearest_node(*m, Vec3(-0.1, 0.025, 0)),
            c = test::nearest_node(*m, Vec3(0.1, 0.025, 0));
  return 0.5 * (x(2, a) + x(2, c)) - 0.004;
}

TEST(RigidEdge, RidgePassesThroughWithoutEdgesAndLiftsTheStripWithThem) {
  const double without = height_over_ridge(false);
  std::vector<std::vector<double>> res;
  double balance = 1;
  const double with = height_over_ridge(true, &res, &balance);
  std::cout << "wedge ridge: the strip's height over it " << without << " m without edge "
            << "contact, " << with << " m with it (contact distance " << 0.5 * kT
            << " m)\nNewton residuals per step:\n";
  for (const auto& r : res) {
    for (double v : r) std::cout << " " << v;
    std::cout << "\n";
  }
  EXPECT_LT(without, -0.003);              // the ridge through the strip
  EXPECT_GT(with, 0.5 * kT * (1 - 0.05));  // on it, within the penalty's give
  EXPECT_LT(with, 0.5 * kT * (1 + 0.05));
  EXPECT_LE(res.back().size(), 4u);
  EXPECT_LT(std::abs(balance), 1e-6);
}

}  // namespace
}  // namespace velum
