// Friction of edge pairs (docs/contact.md, "Sheets"): the upper of two crossing strips
// (crossing_strips.hpp: only edge pairs act) pressed onto the held lower one at its inner nodes,
// then slid along it by its ends. Sliding, the force the lower strip exerts on it (from the
// upper strip's reactions and loads) has a part across the pairs' normal μ times the part along
// it, and every node of the pairs slips; slid a little, they stick and that ratio stays below
// μ. Newton's residuals of the last step show the slip tangent at work.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "crossing_strips.hpp"
#include "pure_newton_run.hpp"
#include "velum/analysis/mechanical_system.hpp"

namespace velum {
namespace {

struct Slide {
  bool completed = false;
  double ratio = 0;  ///< the contact force's part across the normal over its part along it
  int stick = 0, slip = 0;
  std::vector<double> first, residuals;  ///< Newton residuals of the first slide step, the last
};

Slide run_slide(double mu, double slide) {
  test::CrossingStrips o;
  o.held = test::CrossingStrips::Held::kSlid;
  o.mu = mu, o.slide = slide;
  auto mp = test::crossing_strips(o);
  Model& m = *mp;
  MechanicalSystem sys(m);
  State s = test::state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  const test::PureNewtonRun run = test::pure_newton_run(sys, s, 2, 0.1, 1.1);
  Slide out;
  out.completed = run.completed;
  out.first = run.first;
  out.residuals = run.last;
  if (!run.completed) return out;
  const NodePositions x = m.X + sys.displacements(2, s.u);
  // The force on the upper strip from the lower one: minus its supports' reactions and its
  // point loads (its own forces balance).
  const NodePositions R = sys.reactions(2, s.u, s.v);
  Vec3 F = Vec3::Zero();
  for (int i = 0; i < m.num_nodes(); ++i)
    if (m.X(2, i) > 0) {
      F -= R.col(i);
      if (std::abs(m.X(0, i)) < 0.2) F.z() += o.press;  // the inner nodes, pressed down
    }
  // The pairs' normal: the upper strip's middle element's long edge across the lower one's.
  const int a = test::nearest_node(m, Vec3(-0.1, 0.025, o.z0)),
            b = test::nearest_node(m, Vec3(0.1, 0.025, o.z0)),
            c = test::nearest_node(m, Vec3(0.025, -0.1, 0)),
            d = test::nearest_node(m, Vec3(0.025, 0.1, 0));
  Vec3 n = (x.col(b) - x.col(a)).cross(x.col(d) - x.col(c)).normalized();
  if (n.z() < 0) n = -n;
  const double N = F.dot(n), T = (F - N * n).norm();
  out.ratio = T / N;
  const std::vector<double> st = sys.load_node_field("contact_status", 2, x);
  for (double v : st) out.stick += v == 1, out.slip += v == 2;
  std::cout << "slid " << slide << " m, mu " << mu << ": normal force " << N << " N, tangential "
            << T << " N, ratio / mu - 1 = " << out.ratio / mu - 1 << "; nodes stick " << out.stick
            << ", slip " << out.slip << "\nNewton residuals of the first slide step:";
  for (double v : out.first) std::cout << " " << v;
  std::cout << "; of the last:";
  for (double v : out.residuals) std::cout << " " << v;
  std::cout << "\n";
  return out;
}

TEST(EdgeFriction, SlidingCrossingStripIsMuTimesTheNormalForce) {
  for (double mu : {0.2, 0.5}) {
    const Slide sl = run_slide(mu, 0.005);
    ASSERT_TRUE(sl.completed);
    EXPECT_NEAR(sl.ratio / mu, 1.0, 1e-5);
    EXPECT_EQ(sl.stick, 0);
    EXPECT_EQ(sl.slip, 8);  // the four edges of the two pairs' middle elements
    EXPECT_LE(sl.first.size(), 5u);
    EXPECT_LE(sl.residuals.size(), 4u);
  }
}

TEST(EdgeFriction, CrossingStripSticksWhenSlidALittle) {
  const Slide sl = run_slide(0.5, 1e-8);
  ASSERT_TRUE(sl.completed);
  EXPECT_LT(sl.ratio, 0.9 * 0.5);
  EXPECT_GT(sl.ratio, 0.0);
  EXPECT_EQ(sl.stick, 8);
}

// The edge pairs' state (sides, friction anchors) goes through the saved state: a system
// restored from one that slid part of the way has its forces; one started afresh at the same
// positions has not (its pairs anchor where they are).
TEST(EdgeFriction, EdgePairsGoThroughTheSavedState) {
  test::CrossingStrips o;
  o.held = test::CrossingStrips::Held::kSlid;
  o.mu = 0.5, o.slide = 0.005;
  auto m = test::crossing_strips(o);
  MechanicalSystem a(*m), b(*m), c(*m);
  State s = test::state_from(a, NodePositions::Zero(3, m->num_nodes()));
  const test::PureNewtonRun r = test::pure_newton_run(a, s, 1.3, 0.1, -1, false);
  ASSERT_TRUE(r.completed);
  b.restore_load_state(a.save_load_state());
  c.start_loads(1.3, s.u, s.v);
  // A little further along the slide: the anchors of the last accepted state hold.
  const double t = 1.35;
  const VecX zero = VecX::Zero(a.size());
  VecX ra, rb, rc;
  a.evaluate(t, s.u, zero, zero, 1, 0, 0, ra, nullptr);
  b.evaluate(t, s.u, zero, zero, 1, 0, 0, rb, nullptr);
  c.evaluate(t, s.u, zero, zero, 1, 0, 0, rc, nullptr);
  ASSERT_GT(ra.norm(), 0);
  std::cout << "restored: residual difference " << (ra - rb).norm() / ra.norm()
            << "; started afresh: " << (ra - rc).norm() / ra.norm() << "\n";
  EXPECT_LT((ra - rb).norm(), 1e-12 * ra.norm());
  EXPECT_GT((ra - rc).norm(), 1e-3 * ra.norm());
}

}  // namespace
}  // namespace velum
