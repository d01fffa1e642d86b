// Edge-to-edge contact (contact `edges: true`, docs/contact.md "Sheets"): the gap's gradient and
// Hessian against central differences, and two strips one element wide crossing each other:
// no node lies over the other strip's faces, so node to face alone lets the upper strip, pulled
// down at its ends, pass through the lower one; with the edges it rests on it.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "../../verification/model_builders.hpp"
#include "load/edge_contact.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

TEST(EdgeContact, GapDerivativesMatchCentralDifferences) {
  contact::Vec12 X;
  X << 0, 0, 0.01, 1, 0.1, 0.0, 0.3, -0.5, 0.0, 0.4, 0.6, 0.02;
  contact::Vec12 g;
  contact::Mat12 H;
  const double v = contact::edge_gap(X, g, &H);
  // The gap is the distance of the closest points.
  double s = 0, t = 0;
  ASSERT_TRUE(contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6),
                                       X.segment<3>(9), s, t));
  const Vec3 p = X.segment<3>(0) + s * (X.segment<3>(3) - X.segment<3>(0));
  const Vec3 q = X.segment<3>(6) + t * (X.segment<3>(9) - X.segment<3>(6));
  EXPECT_NEAR(std::abs(v), (p - q).norm(), 1e-14);
  contact::Vec12 fg;
  contact::Mat12 fH;
  const double h = 1e-6;
  for (int j = 0; j < 12; ++j) {
    contact::Vec12 a = X, b = X, ga, gb;
    a[j] += h, b[j] -= h;
    fg[j] = (contact::edge_gap(a, ga, nullptr) - contact::edge_gap(b, gb, nullptr)) / (2 * h);
    fH.col(j) = (ga - gb) / (2 * h);
  }
  std::cout << "edge gap: gradient " << (fg - g).norm() / g.norm() << ", Hessian "
            << (fH - H).norm() / H.norm() << " against central differences\n";
  EXPECT_LT((fg - g).norm() / g.norm(), 1e-8);
  EXPECT_LT((fH - H).norm() / H.norm(), 1e-7);
}

constexpr double kT = 1e-3, kZ0 = 0.002, kDrop = 0.006;

// The lower strip along y (held), the upper along x (prestressed, its ends moved down by
// kDrop, its middle nodes free in z), one self-contact set; returns the upper strip's least
// height over the lower one's edges where they cross.
double crossing_height(bool edges, int* iterations = nullptr) {
  Model m;
  for (int layer = 0; layer < 2; ++layer) {
    test::NodeCache nodes(m, 1e-9);
    std::vector<int> conn;
    test::mesh_patch(
        nodes,
        [&](double u, double v) {
          const double along = -0.2 + 0.6 * u, across = -0.025 + 0.05 * v;
          return layer ? Vec3(along, across, kZ0) : Vec3(across, along, 0.0);
        },
        2, 1, "quad4", conn);
    const double S = layer ? 1000.0 / kT : 0.0;
    test::add_membrane(
        m, "quad4", std::move(conn),
        SheetLaw(PlaneStressLaw::isotropic("iso", 1e9, 0.3)).with_prestress({S, S, 0}), 1000.0, kT);
  }
  std::vector<int> lower, ends, middle;
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Vec3 X = m.X.col(i);
    if (X.z() < 0.5 * kZ0)
      lower.push_back(i);
    else if (std::abs(X.x() - 0.1) < 1e-9)
      middle.push_back(i);
    else
      ends.push_back(i);
  }
  m.fixed.push_back({lower, {true, true, true}});
  m.fixed.push_back({middle, {true, true, false}});
  m.prescribed.push_back({ends, Vec3(0, 0, -kDrop), test::add_ramp(m, 1.0)});
  ContactLoad cl;
  cl.self = true;
  cl.edges = edges;
  for (int b = 0; b < 2; ++b) {
    cl.parts.push_back({b, {}});
    for (int e = 0; e < m.blocks[static_cast<size_t>(b)]->size(); ++e)
      cl.parts.back().elements.push_back(e);
  }
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  MechanicalSystem sys(m);
  State s = test::state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1, loop.step = 0.1;
  int most = 0;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        most = std::max(most, st.report->iterations);
        return true;
      });
  EXPECT_TRUE(r.completed) << r.reason;
  if (iterations) *iterations = most;
  const NodePositions x = m.X + sys.displacements(1, s.u);
  // The upper strip's long edges at x = ±0.025 (the lower strip's edges).
  double least = 1;
  for (int side : {-1, 1}) {
    const double y = 0.025 * side;
    const int a = test::nearest_node(m, Vec3(-0.2, y, kZ0)),
              b = test::nearest_node(m, Vec3(0.1, y, kZ0));
    for (double cx : {-0.025, 0.025}) {
      const double u = (cx - x(0, a)) / (x(0, b) - x(0, a));
      least = std::min(least, x(2, a) + u * (x(2, b) - x(2, a)));
    }
  }
  return least;
}

TEST(EdgeContact, CrossingStripsPassThroughWithoutEdgesAndRestWithThem) {
  const double without = crossing_height(false);
  int iterations = 0;
  const double with = crossing_height(true, &iterations);
  std::cout << "crossing strips: the upper one's least height over the lower's edges " << without
            << " m without edge contact, " << with << " m with it (contact distance " << kT
            << " m; at most " << iterations << " Newton iterations a step)\n";
  EXPECT_LT(without, 0.0);           // through the lower strip
  EXPECT_GT(with, kT * (1 - 0.05));  // on it, within the penalty's give
  EXPECT_LT(with, kT * (1 + 0.05));  // resting, not held off
}

}  // namespace
}  // namespace velum
