// Friction between sheets (docs/contact.md, "Sheets"): the pair's friction force against
// central differences (stick and slip), and a small sheet pressed onto a held one and pulled
// along it by one edge: sliding, the pull (the pulled edge's reaction) is μ times the normal
// force, every touching node slips; pulled a little, the nodes stick and the pull stays below.
// The pull: the reactions of the pulled edges along x.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "../../verification/model_builders.hpp"
#include "load/face_contact.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

// The pair's force with friction at X (anchor fixed).
contact::Vec12 friction_force(const contact::Vec12& X, const Vec2& xi0, double mu, bool tangent,
                              contact::Mat12* D, contact::Status* status = nullptr) {
  contact::PairResult r;
  if (!contact::pair_force(X, 1.0, 0.01, 1e5, tangent, r)) return contact::Vec12::Zero();
  Vec3 slip;
  const contact::Status s = contact::pair_friction(X, 1.0, 0.01, 1e5, mu, xi0, tangent, r, slip);
  if (status) *status = s;
  if (D) *D = r.D;
  return r.f;
}

TEST(SheetFriction, PairTangentMatchesCentralDifferences) {
  contact::Vec12 X;
  X << 0.3, 0.25, 0.005, 0, 0, 0, 1, 0.1, 0.02, 0.1, 1, -0.03;  // node 5 mm above the face
  // The node's projection on the face, and anchors near it (stick) and farther (slip).
  const Vec2 xi = contact::plane_coordinates(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6),
                                             X.segment<3>(9));
  for (const auto& [xi0, mu, want] :
       {std::tuple{Vec2(xi + Vec2(1e-3, -5e-4)), 0.5, contact::Status::kStick},
        std::tuple{Vec2(xi + Vec2(0.05, -0.03)), 0.3, contact::Status::kSlip}}) {
    contact::Mat12 D;
    contact::Status status;
    const contact::Vec12 f = friction_force(X, xi0, mu, true, &D, &status);
    ASSERT_EQ(status, want);
    // No net force on the pair.
    EXPECT_LT((f.segment<3>(0) + f.segment<3>(3) + f.segment<3>(6) + f.segment<3>(9)).norm(),
              1e-9 * f.norm());
    contact::Mat12 fd;
    const double h = 1e-7;
    for (int j = 0; j < 12; ++j) {
      contact::Vec12 p = X, m = X;
      p[j] += h, m[j] -= h;
      fd.col(j) = (friction_force(p, xi0, mu, false, nullptr) -
                   friction_force(m, xi0, mu, false, nullptr)) /
                  (2 * h);
    }
    const double err = (fd - D).norm() / D.norm();
    std::cout << (want == contact::Status::kStick ? "stick" : "slip")
              << ": tangent against central differences " << err << "\n";
    EXPECT_LT(err, 1e-7);
  }
}

constexpr double kSheetThickness = 1e-3, kSheetModulus = 1e9, kPressure = 2000.0;

struct Pulled {
  std::unique_ptr<Model> m;
  std::vector<int> pulled, touching;
};

// A held sheet 0.4 m (8 x 8 quads) and on it a prestressed sheet 0.2 m (4 x 4), offset by a
// quarter element, pressed by q on its nodes' areas and pulled along x by its two edges across
// x (moved by `pull` over t in [0, 1]: the edges hold its prestress); held across (y).
Pulled pulled_sheet(double mu, double pull) {
  Pulled out;
  out.m = std::make_unique<Model>();
  Model& m = *out.m;
  const double h = 0.05, x0 = 0.1 + h / 4;
  for (int layer = 0; layer < 2; ++layer) {
    test::NodeCache nodes(m, 1e-9);
    std::vector<int> conn;
    const double a = layer ? 0.2 : 0.4, o = layer ? x0 : 0.0;
    test::mesh_patch(
        nodes,
        [&](double u, double v) { return Vec3(o + a * u, o + a * v, layer * kSheetThickness); },
        layer ? 4 : 8, layer ? 4 : 8, "quad4", conn);
    const double S = layer ? 1000.0 / kSheetThickness : 0.0;
    test::add_membrane(
        m, "quad4", std::move(conn),
        SheetLaw(PlaneStressLaw::isotropic("iso", kSheetModulus, 0.3)).with_prestress({S, S, 0}),
        1000.0, kSheetThickness);
  }
  std::vector<int> lower, upper;
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Vec3 X = m.X.col(i);
    if (X.z() < 0.5 * kSheetThickness) {
      lower.push_back(i);
      continue;
    }
    upper.push_back(i);
    if (X.x() < x0 + 1e-9 || X.x() > x0 + 0.2 - 1e-9) {
      out.pulled.push_back(i);
      continue;
    }
    out.touching.push_back(i);
    // The node's area: h² inside, halved on an edge.
    const bool ey = X.y() < x0 + 1e-9 || X.y() > x0 + 0.2 - 1e-9;
    const double area = h * h * (ey ? 0.5 : 1.0);
    m.point_loads.push_back({{i}, Vec3(0, 0, -kPressure * area), -1});
  }
  m.fixed.push_back({lower, {true, true, true}});
  m.fixed.push_back({upper, {false, true, false}});
  m.prescribed.push_back({out.pulled, Vec3(pull, 0, 0), test::add_ramp(m, 1.0)});
  ContactLoad cl;
  cl.parts.push_back({1, {}});
  cl.other.push_back({0, {}});
  for (int e = 0; e < m.blocks[0]->size(); ++e) cl.other[0].elements.push_back(e);
  for (int e = 0; e < m.blocks[1]->size(); ++e) cl.parts[0].elements.push_back(e);
  cl.friction = mu;
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  return out;
}

struct Pull {
  double ratio = 0;  // the pull over μ N
  int stick = 0, slip = 0;
  bool completed = false;
};

Pull run_pull(double mu, double pull) {
  Pulled p = pulled_sheet(mu, pull);
  MechanicalSystem sys(*p.m);
  State s = test::state_from(sys, NodePositions::Zero(3, p.m->num_nodes()));
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
  Pull out;
  out.completed = r.completed;
  if (!r.completed) {
    std::cout << "not completed: " << r.reason << "\n";
    return out;
  }
  std::cout << "Newton residuals of the last step:";
  for (double v : reports.back().residuals) std::cout << " " << v;
  std::cout << "\n";
  const NodePositions x = p.m->X + sys.displacements(1, s.u);
  const double N = -*sys.loads().back()->quantity_at("contact_force:contact=0:2", 1, x);
  const NodePositions R = sys.reactions(1, s.u, s.v);
  double Rx = 0;
  for (int n : p.pulled) Rx += R(0, n);
  out.ratio = Rx / (mu * N);
  const std::vector<double> st = sys.load_node_field("contact_status", 1, x);
  for (int n : p.touching) {
    out.stick += st[static_cast<size_t>(n)] == 1;
    out.slip += st[static_cast<size_t>(n)] == 2;
  }
  std::cout << "pull " << pull << ", mu " << mu << ": normal force " << N << " N, pull " << Rx
            << " N, pull / (mu N) " << out.ratio << "; touching nodes stick " << out.stick
            << ", slip " << out.slip << " of " << p.touching.size() << "\n";
  return out;
}

TEST(SheetFriction, SlidingSheetPullIsMuTimesTheNormalForce) {
  for (double mu : {0.2, 0.5}) {
    const Pull p = run_pull(mu, 0.01);
    ASSERT_TRUE(p.completed);
    EXPECT_NEAR(p.ratio, 1.0, 3e-3);
    EXPECT_EQ(p.stick, 0);
    EXPECT_EQ(p.slip, 15);
  }
}

TEST(SheetFriction, SheetSticksUnderASmallPull) {
  const Pull p = run_pull(0.5, 2e-7);
  ASSERT_TRUE(p.completed);
  EXPECT_LT(p.ratio, 0.9);
  EXPECT_GT(p.ratio, 0.0);
  EXPECT_EQ(p.stick, 15);
}

}  // namespace
}  // namespace velum
