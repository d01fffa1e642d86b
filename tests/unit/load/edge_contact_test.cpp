// Edge-to-edge contact (contact `edges: true`, docs/contact.md "Sheets"): the gap's gradient and
// Hessian and the pair's tangent (frictionless, sticking, slipping) against central
// differences; the whole term's matrix (K and its low-rank part) against central differences
// of its forces on two crossing strips of an anisotropic sheet; and the crossing strips under
// load: no node lies over the other strip's faces, so node to face alone lets the upper strip,
// pulled down at its ends, pass through the lower one; with the edges it rests on it, and
// Newton converges quadratically once the pairs are settled.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "crossing_strips.hpp"
#include "load/edge_contact.hpp"
#include "reused_candidates.hpp"
#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
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

// The pair's force at X: the penalty and, with μ > 0, friction from the anchor st0.
contact::Vec12 edge_pair(const contact::Vec12& X, double mu, const Vec2& st0, bool tangent,
                         contact::Mat12* D, contact::Status* status = nullptr) {
  contact::PairResult r;
  if (!contact::edge_pair_force(X, 1.0, 0.01, 1e5, tangent, r)) return contact::Vec12::Zero();
  contact::Status s = contact::Status::kSlip;
  double keep = 1;
  if (mu > 0) s = contact::edge_friction(X, 1.0, 0.01, 1e5, mu, st0, tangent, r, keep);
  if (status) *status = s;
  if (D) *D = r.D;
  return r.f;
}

TEST(EdgeContact, PairTangentMatchesCentralDifferences) {
  // Two edges crossing 5 mm apart (contact distance 1 cm), neither parallel to an axis.
  contact::Vec12 X;
  X << -0.4, -0.1, 0.005, 0.6, 0.15, 0.008, 0.05, -0.5, 0.0, -0.1, 0.45, -0.002;
  double s = 0, t = 0;
  ASSERT_TRUE(contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6),
                                       X.segment<3>(9), s, t));
  for (const auto& [st0, mu, want, what] :
       {std::tuple{Vec2(s, t), 0.0, contact::Status::kSlip, "frictionless"},
        std::tuple{Vec2(s + 1e-3, t - 5e-4), 0.5, contact::Status::kStick, "stick"},
        std::tuple{Vec2(s + 0.05, t - 0.03), 0.3, contact::Status::kSlip, "slip"}}) {
    contact::Mat12 D;
    contact::Status status;
    const contact::Vec12 f = edge_pair(X, mu, st0, true, &D, &status);
    ASSERT_EQ(status, want) << what;
    ASSERT_GT(f.norm(), 0);
    // No net force on the pair.
    EXPECT_LT((f.segment<3>(0) + f.segment<3>(3) + f.segment<3>(6) + f.segment<3>(9)).norm(),
              1e-9 * f.norm());
    contact::Mat12 fd;
    const double h = 1e-7;
    for (int j = 0; j < 12; ++j) {
      contact::Vec12 p = X, m = X;
      p[j] += h, m[j] -= h;
      fd.col(j) =
          (edge_pair(p, mu, st0, false, nullptr) - edge_pair(m, mu, st0, false, nullptr)) / (2 * h);
    }
    const double err = (fd - D).norm() / D.norm();
    std::cout << "edge pair, " << what << ": tangent against central differences " << err << "\n";
    EXPECT_LT(err, 1e-7) << what;
  }
}

// The crossing strips held at their ends, the upper one 0.7 mm over the lower (0.3 mm into
// the contact distance): the term started (anchored) at u = 0, its matrix checked at u0 =
// 1 µm at random, plus `shift` along x at the upper strip's free nodes; then accepted there,
// every node of the four edge pairs has `status`.
void check_term_matrix(double mu, double shift, contact::Status status, const char* what) {
  test::CrossingStrips o;
  o.z0 = 0.7e-3, o.mu = mu, o.held = test::CrossingStrips::Held::kEndsHeld;
  auto m = test::crossing_strips(o);
  MechanicalSystem sys(*m);
  const int n = sys.size();
  const VecX zero = VecX::Zero(n);
  sys.start_loads(0, zero, zero);
  std::srand(5);
  VecX u0 = 1e-6 * VecX::Random(n);
  NodePositions U = NodePositions::Zero(3, m->num_nodes());
  for (int i = 0; i < m->num_nodes(); ++i)
    if (m->X(2, i) > 0) U(0, i) = shift;
  VecX s;
  sys.dofs().gather(U, s);
  u0 += s;
  MatX J;
  const VecX f = term_forces(sys, kLastTerm, u0, &J);
  ASSERT_GT(f.norm(), 0);
  const double err = term_matrix_error(sys, kLastTerm, u0, J, 1e-9);
  std::cout << "crossing strips, " << what << ": term matrix against central differences " << err
            << " (" << n << " equations)\n";
  EXPECT_LT(err, 1e-6) << what;
  sys.accept(0, u0, zero);
  const std::string account = sys.loads().back()->account_json();
  EXPECT_NE(account.find("\"active_edge_pairs\": 4"), std::string::npos) << account;
  const NodePositions x = m->X + sys.displacements(0, u0);
  const std::vector<double> st = sys.load_node_field("contact_status", 0, x);
  int touching = 0;
  for (double v : st) {
    if (!(v > 0)) continue;
    EXPECT_EQ(v, static_cast<double>(status)) << what;
    ++touching;
  }
  EXPECT_EQ(touching, 8) << what;  // both long edges of each strip's middle element
}

// The anisotropic crossing strips 0.3 mm into the contact distance, with their edge pairs
// (searched at every evaluation): the node-to-face candidates reused (skin 0.5 mm) give a
// fresh search's forces and matrix.
TEST(EdgeContact, ReusedCandidatesGiveAFreshSearchsForcesAndMatrix) {
  test::CrossingStrips o;
  o.z0 = 0.7e-3, o.held = test::CrossingStrips::Held::kEndsHeld;
  auto m = test::crossing_strips(o);
  test::check_reused_candidates(*m, 2e-4, 2e-3, "crossing strips");
}

TEST(EdgeContact, TermMatrixMatchesFiniteDifferences) {
  check_term_matrix(0.0, 0.0, contact::Status::kSlip, "frictionless");
  check_term_matrix(0.5, 0.0, contact::Status::kStick, "friction, stick");
  check_term_matrix(0.5, 1e-3, contact::Status::kSlip, "friction, slip");
}

// The crossing strips pulled down (CrossingStrips::kPulledDown) in 10 static steps; returns
// the upper strip's least height over the lower one's edges where they cross, and the
// Newton residuals of each step.
double crossing_height(bool edges, std::vector<std::vector<double>>* residuals = nullptr) {
  test::CrossingStrips o;
  o.edges = edges;
  auto mp = test::crossing_strips(o);
  Model& m = *mp;
  MechanicalSystem sys(m);
  State s = test::state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
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
  const NodePositions x = m.X + sys.displacements(1, s.u);
  // The upper strip's long edges at x = ±0.025 (the lower strip's edges).
  double least = 1;
  for (int side : {-1, 1}) {
    const double y = 0.025 * side;
    const int a = test::nearest_node(m, Vec3(-0.1, y, o.z0)),
              b = test::nearest_node(m, Vec3(0.1, y, o.z0));
    for (double cx : {-0.025, 0.025}) {
      const double u = (cx - x(0, a)) / (x(0, b) - x(0, a));
      least = std::min(least, x(2, a) + u * (x(2, b) - x(2, a)));
    }
  }
  return least;
}

// Both strips held at their ends only and the upper one pressed onto the lower one at its
// middle: the edge pairs couple free nodes of both strips, so Newton is quadratic only with
// their coupling in the Jacobian.
TEST(EdgeContact, NewtonIsQuadraticOnceEdgePairsSettle) {
  test::CrossingStrips o;
  o.held = test::CrossingStrips::Held::kPressed;
  auto m = test::crossing_strips(o);
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  integrator.newton.reuse_tangent = false;  // a fresh tangent at every iteration: pure Newton
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = 1, loop.step = 0.1;
  std::vector<std::vector<double>> res;
  std::vector<int> pairs;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        res.push_back(st.report->residuals);
        const std::string a = sys.loads().back()->account_json();
        pairs.push_back(std::stoi(a.substr(a.find("active_edge_pairs") + 20)));
        return true;
      });
  ASSERT_TRUE(r.completed) << r.reason;
  std::cout << "pressed crossing strips, Newton residuals per step (active edge pairs):\n";
  for (size_t k = 0; k < res.size(); ++k) {
    std::cout << " (" << pairs[k] << ")";
    for (double v : res[k]) std::cout << " " << v;
    std::cout << "\n";
  }
  const NodePositions x = m->X + sys.displacements(1, s.u);
  const int up = test::nearest_node(*m, Vec3(0.1, 0.025, o.z0));
  const int low = test::nearest_node(*m, Vec3(0.025, 0.1, 0));
  std::cout << "upper middle at z = " << x(2, up) << ", lower middle at z = " << x(2, low) << "\n";
  EXPECT_LT(x(2, low), -1e-4);  // the lower strip pushed down by the upper one
  EXPECT_EQ(pairs.back(), 4);
  // The last steps, pairs settled: each iteration squares the relative residual (within a
  // factor), down to the round-off floor in at most three iterations.
  for (size_t k = res.size() - 3; k < res.size(); ++k) {
    const std::vector<double>& q = res[k];
    EXPECT_LE(q.size(), 4u);
    for (size_t i = 1; i + 1 < q.size(); ++i) {
      const double r1 = q[i] / q[0], r0 = q[i - 1] / q[0];
      EXPECT_LT(r1, 100 * r0 * r0 + 1e-11) << "step " << k << " iteration " << i;
    }
  }
}

TEST(EdgeContact, CrossingStripsPassThroughWithoutEdgesAndRestWithThem) {
  const double T = test::CrossingStrips().thickness;
  const double without = crossing_height(false);
  std::vector<std::vector<double>> res;
  const double with = crossing_height(true, &res);
  std::cout << "crossing strips: the upper one's least height over the lower's edges " << without
            << " m without edge contact, " << with << " m with it (contact distance " << T
            << " m)\nNewton residuals per step:\n";
  for (const auto& r : res) {
    for (double v : r) std::cout << " " << v;
    std::cout << "\n";
  }
  EXPECT_LT(without, 0.0);          // through the lower strip
  EXPECT_GT(with, T * (1 - 0.05));  // on it, within the penalty's give
  EXPECT_LT(with, T * (1 + 0.05));  // resting, not held off
}

}  // namespace
}  // namespace velum
