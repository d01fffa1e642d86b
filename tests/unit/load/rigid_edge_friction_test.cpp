// Coulomb friction of edge contact with a rigid mesh (`edges: true` with `friction`,
// docs/contact.md "Rigid meshes"): the strip's sides against the wedge's ridge, with the sheets'
// edge kernel and regularised Coulomb return. The term's matrix against central differences in
// stick and in slip (a wedge moved and turned by its motion, and a free wedge); the strip
// pressed onto the ridge and slid along it by its ends: the force each side takes across the
// pair's normal is μ times the force along it (slip), or less (stick, slid a little).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "pure_newton_run.hpp"
#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "wedge_strip.hpp"

namespace velum {
namespace {

void add_contact(Model& m, const RigidBody& body, double mu, int body_node = -1) {
  ContactLoad cl;
  cl.body = body;
  cl.edges = true;
  cl.friction = mu;
  cl.body_node = body_node;
  cl.parts.push_back({0, {0, 1, 2}});
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
}

// The strip's two sides that cross the ridge (their nodes at x = ±0.1, y = ±0.025): per side
// the force the term puts on its two nodes, its part across the pair's normal over its part
// along it (the ridge along `ridge`).
std::vector<double> side_ratios(const Model& m, const NodePositions& x, const NodePositions& F,
                                const Vec3& ridge) {
  std::vector<double> out;
  for (const double y : {-0.025, 0.025}) {
    const int a = test::nearest_node(m, Vec3(-0.1, y, 0)),
              b = test::nearest_node(m, Vec3(0.1, y, 0));
    const Vec3 n = (x.col(b) - x.col(a)).cross(ridge).normalized();
    const Vec3 f = F.col(a) + F.col(b);
    const double N = f.dot(n);
    out.push_back((f - N * n).norm() / std::abs(N));
  }
  return out;
}

TEST(RigidEdgeFriction, TermMatrixMatchesFiniteDifferencesInStickAndSlip) {
  const double mu = 0.3;
  for (const bool free : {false, true})
    for (const bool slip : {false, true}) {
      auto m = test::strip(true);
      RigidBody b = test::wedge(0.2e-3);
      int node = -1;
      Vec3 ridge = Vec3::UnitY();
      if (free) {
        node = m->add_node(1000, b.point);
        m->masses.push_back({node, 5.0});
      } else {
        b.rotation = Vec3(0.01, 0.005, 0.3), b.displacement = Vec3(0.002, 0.001, 0.0);
        b.pivot = Vec3(0, 0, 0.2e-3);
        ridge = Eigen::AngleAxisd(b.rotation.norm(), b.rotation.normalized()) * ridge;
      }
      add_contact(*m, b, mu, node);
      MechanicalSystem sys(*m);
      const int n = sys.size();
      // The pairs anchor where they are at the start; then the strip's inner nodes are moved
      // along the ridge by 1 mm (slip: past μ p / k = 0.2 mm) or not (stick), and a little at
      // random.
      sys.start_loads(0, VecX::Zero(n), VecX::Zero(n));
      NodePositions shift = NodePositions::Zero(3, m->num_nodes());
      if (slip)
        for (int i = 0; i < m->num_nodes(); ++i)
          if (i != node && std::abs(m->X(0, i)) < 0.2) shift.col(i) = 1e-3 * ridge;
      VecX u;
      sys.dofs().gather(shift, u);
      std::srand(5);
      u += 1e-5 * VecX::Random(n);
      MatX J;
      const VecX f = term_forces(sys, 0, u, &J);
      ASSERT_GT(f.norm(), 0);
      const double err = term_matrix_error(sys, 0, u, J, 1e-9);
      NodePositions Fn = NodePositions::Zero(3, m->num_nodes());
      sys.dofs().scatter(f, Fn);
      const std::vector<double> ratio = side_ratios(*m, m->X + sys.displacements(0, u), Fn, ridge);
      std::cout << "wedge ridge with friction " << mu << ", " << (slip ? "slip" : "stick") << " "
                << (free ? "(free body)" : "(moved, turned)")
                << ": term matrix against central differences " << err
                << "; the sides' force ratios " << ratio[0] << ", " << ratio[1] << "\n";
      EXPECT_LT(err, 1e-6);
      for (const double r : ratio) {
        if (slip) {
          EXPECT_NEAR(r, mu, 1e-9);
        } else {
          EXPECT_LT(r, 0.9 * mu);
        }
      }
      if (free) {
        EXPECT_LT(Fn.rowwise().sum().norm(), 1e-9 * f.norm());
      }
    }
}

struct RidgeSlide {
  bool completed = false;
  std::vector<double> ratio;  ///< per side crossing the ridge
  int stick = 0, slip = 0;
  std::vector<double> first, last;  ///< Newton residuals of the first slide step, the last
};

// The strip pressed onto a fixed wedge (its ridge 1 mm below the strip) by 2 N at each inner
// node up to t = 1, then its ends moved along the ridge by `slide` up to t = 2 (static).
RidgeSlide run_ridge_slide(double mu, double slide) {
  auto m = test::strip(true, slide);
  add_contact(*m, test::wedge(-1e-3), mu);
  MechanicalSystem sys(*m);
  State s = test::state_from(sys, NodePositions::Zero(3, m->num_nodes()));
  const test::PureNewtonRun run = test::pure_newton_run(sys, s, 2, 0.1, 1.1);
  RidgeSlide out;
  out.completed = run.completed;
  out.first = run.first;
  out.last = run.last;
  if (!run.completed) return out;
  const NodePositions x = m->X + sys.displacements(2, s.u);
  const VecX f = term_forces(sys, kLastTerm, s.u, nullptr);
  NodePositions F = NodePositions::Zero(3, m->num_nodes());
  sys.dofs().scatter(f, F);
  out.ratio = side_ratios(*m, x, F, Vec3::UnitY());
  const std::vector<double> st = sys.load_node_field("contact_status", 2, x);
  for (double v : st) out.stick += v == 1, out.slip += v == 2;
  std::cout << "strip slid " << slide << " m along the ridge, mu " << mu << ": the sides' force "
            << "ratios / mu - 1 = " << out.ratio[0] / mu - 1 << ", " << out.ratio[1] / mu - 1
            << "; nodes stick " << out.stick << ", slip " << out.slip
            << "\nNewton residuals of the first slide step:";
  for (double v : out.first) std::cout << " " << v;
  std::cout << "; of the last:";
  for (double v : out.last) std::cout << " " << v;
  std::cout << "\n";
  return out;
}

TEST(RigidEdgeFriction, SlidingStripIsMuTimesTheNormalForce) {
  for (const double mu : {0.2, 0.5}) {
    const RidgeSlide sl = run_ridge_slide(mu, 0.005);
    ASSERT_TRUE(sl.completed);
    for (const double r : sl.ratio) EXPECT_NEAR(r / mu, 1.0, 1e-6);
    EXPECT_EQ(sl.stick, 0);
    EXPECT_EQ(sl.slip, 4);  // the two sides' inner nodes
    EXPECT_LE(sl.first.size(), 6u);
    EXPECT_LE(sl.last.size(), 5u);
  }
}

TEST(RigidEdgeFriction, StripSticksWhenSlidALittle) {
  const RidgeSlide sl = run_ridge_slide(0.5, 1e-8);
  ASSERT_TRUE(sl.completed);
  for (const double r : sl.ratio) {
    EXPECT_LT(r, 0.9 * 0.5);
    EXPECT_GT(r, 0.0);
  }
  EXPECT_EQ(sl.stick, 4);
}

// The pairs' anchors go through the saved state: a system restored from one that slid part of
// the way has its forces; one started afresh at the same positions has not (its pairs anchor
// where they are).
TEST(RigidEdgeFriction, AnchorsGoThroughTheSavedState) {
  auto m = test::strip(true, 0.005);
  add_contact(*m, test::wedge(-1e-3), 0.5);
  MechanicalSystem a(*m), b(*m), c(*m);
  State s = test::state_from(a, NodePositions::Zero(3, m->num_nodes()));
  const test::PureNewtonRun r = test::pure_newton_run(a, s, 1.3, 0.1, -1, false);
  ASSERT_TRUE(r.completed);
  b.restore_load_state(a.save_load_state());
  c.start_loads(1.3, s.u, s.v);
  const double t = 1.35;  // a little further along the slide
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
