// Sheet–sheet and self contact (docs/contact.md, "Sheets"): the node-to-face pair's tangent
// against central differences, the face tree against a search of every face, two sheets
// pressed together (force balance, penetration within tolerance) and a sheet folded onto
// itself under a load (the layers kept apart), static and implicit dynamic; initial
// penetrations reported and relaxed.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "../../verification/model_builders.hpp"
#include "load/face_contact.hpp"
#include "load/face_tree.hpp"
#include "reused_candidates.hpp"
#include "term_forces.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {
namespace {

using contact::Mat12;
using contact::Vec12;

TEST(SheetContact, PairTangentMatchesCentralDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  for (double side : {1.0, -1.0}) {
    Vec12 X;
    X << 0.3, 0.25, side * 0.01, 0, 0, 0, 1, 0, 0, 0, 1, 0;
    for (int i = 0; i < 12; ++i) X[i] += 0.1 * jitter(rng);
    const double c = 0.05, k = 1e3;
    contact::PairResult r;
    ASSERT_TRUE(contact::pair_force(X, side, c, k, true, r));
    Mat12 fd;
    const double h = 1e-6;
    for (int j = 0; j < 12; ++j) {
      Vec12 Xp = X, Xm = X;
      Xp[j] += h, Xm[j] -= h;
      contact::PairResult rp, rm;
      contact::pair_force(Xp, side, c, k, false, rp);
      contact::pair_force(Xm, side, c, k, false, rm);
      fd.col(j) = (rp.f - rm.f) / (2 * h);
    }
    const double err = (fd - r.D).norm() / r.D.norm();
    std::cout << "side " << side << ": gap " << r.gap << ", tangent error " << err << "\n";
    EXPECT_LT(err, 1e-7);
    EXPECT_LT((r.D - r.D.transpose()).norm(), 1e-12 * r.D.norm());  // an energy's Hessian
    // The pair's forces balance (no net force, no net moment).
    Vec3 net = Vec3::Zero(), moment = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      net += r.f.segment<3>(3 * a);
      moment += Vec3(X.segment<3>(3 * a)).cross(Vec3(r.f.segment<3>(3 * a)));
    }
    EXPECT_LT(net.norm(), 1e-12 * r.f.norm());
    EXPECT_LT(moment.norm(), 1e-12 * r.f.norm());
  }
}

// The plane gap's Hessian in closed form (plane_gap) against the forward differentiation of
// its gradient that it replaced, and against central differences of the gradient, on random
// triangles away from degenerate (their area at least a tenth of their longest side squared).
TEST(SheetContact, GapHessianInClosedFormMatchesForwardDifferentiation) {
  using AD = Eigen::AutoDiffScalar<Vec12>;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst_ad = 0, worst_grad = 0, worst_fd = 0;
  int tried = 0;
  while (tried < 200) {
    Vec12 X;
    for (int i = 0; i < 12; ++i) X[i] = u(rng);
    const Vec3 a = X.segment<3>(3), b = X.segment<3>(6), c = X.segment<3>(9);
    const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
    if ((b - a).cross(c - a).norm() < 0.2 * longest * longest) continue;
    ++tried;
    Vec12 grad;
    Mat12 H;
    const double g = contact::plane_gap(X, grad, &H);
    // The reference: the gradient's forward derivative (as plane_gap computed it before).
    Eigen::Matrix<AD, 12, 1> Y;
    for (int i = 0; i < 12; ++i) Y[i] = AD(X[i], 12, i);
    AD g_ad;
    const Eigen::Matrix<AD, 12, 1> G = contact::plane_gap_gradient<AD>(Y, &g_ad);
    Mat12 H_ad;
    Vec12 grad_ad;
    for (int i = 0; i < 12; ++i) grad_ad[i] = G[i].value(), H_ad.row(i) = G[i].derivatives();
    EXPECT_NEAR(g, g_ad.value(), 1e-15);
    worst_grad = std::max(worst_grad, (grad - grad_ad).norm() / grad_ad.norm());
    worst_ad = std::max(worst_ad, (H - H_ad).norm() / H_ad.norm());
    Mat12 fd;
    const double h = 1e-6;
    for (int j = 0; j < 12; ++j) {
      Vec12 Xp = X, Xm = X, gp, gm;
      Xp[j] += h, Xm[j] -= h;
      contact::plane_gap(Xp, gp, nullptr);
      contact::plane_gap(Xm, gm, nullptr);
      fd.col(j) = (gp - gm) / (2 * h);
    }
    worst_fd = std::max(worst_fd, (fd - H).norm() / H.norm());
  }
  std::cout << "plane gap, 200 triangles: gradient against forward differentiation " << worst_grad
            << ", Hessian " << worst_ad << ", Hessian against central differences " << worst_fd
            << "\n";
  EXPECT_LT(worst_grad, 1e-13);
  EXPECT_LT(worst_ad, 1e-12);
  EXPECT_LT(worst_fd, 1e-7);
}

TEST(SheetContact, FaceTreeFindsWhatEveryFaceHolds) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<contact::Box> boxes(5000);
  for (auto& b : boxes) {
    const Vec3 c(u(rng), u(rng), 0.1 * u(rng));
    b = contact::Box(c - Vec3::Constant(0.01), c + Vec3::Constant(0.01));
  }
  contact::FaceTree tree;
  tree.build(boxes);
  for (auto& b : boxes) b.translate(Vec3(0.003, 0, 0));  // moved: refitted, not rebuilt
  tree.refit(boxes);
  for (int q = 0; q < 500; ++q) {
    const Vec3 p(u(rng), u(rng), 0.1 * u(rng));
    std::vector<int> found, all;
    tree.query(p, [&](int f) { found.push_back(f); });
    for (size_t f = 0; f < boxes.size(); ++f)
      if (boxes[f].contains(p)) all.push_back(static_cast<int>(f));
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found, all);
  }
}

// Faces that move far from those they were grouped with (the sheet folded over itself): the
// refitted boxes overlap ever more, so refit() builds the tree afresh once their volume has
// doubled; the queries stay exact either way.
TEST(SheetContact, FaceTreeRebuildsWhenFacesMoveApart) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<contact::Box> boxes(4000);
  for (auto& b : boxes) {
    const Vec3 c(u(rng), u(rng), 0.1 * u(rng));
    b = contact::Box(c - Vec3::Constant(0.01), c + Vec3::Constant(0.01));
  }
  contact::FaceTree tree;
  tree.build(boxes);
  for (auto& b : boxes) b.translate(Vec3(0.002, 0, 0));  // a small move: refitted only
  tree.refit(boxes);
  EXPECT_EQ(tree.rebuilds(), 0);
  EXPECT_LT(tree.looseness(), 1.1);
  // Half the faces folded over: x mirrored about the middle.
  for (size_t f = 0; f < boxes.size(); f += 2) {
    const Vec3 c = boxes[f].center();
    const Vec3 m(1.0 - c.x(), c.y(), c.z() + 0.2);
    boxes[f] = contact::Box(m - Vec3::Constant(0.01), m + Vec3::Constant(0.01));
  }
  tree.refit(boxes);
  EXPECT_EQ(tree.rebuilds(), 1);
  EXPECT_LT(tree.looseness(), 1.5);
  for (int q = 0; q < 500; ++q) {
    const Vec3 p(u(rng), u(rng), 0.3 * u(rng));
    std::vector<int> found, all;
    tree.query(p, [&](int f) { found.push_back(f); });
    for (size_t f = 0; f < boxes.size(); ++f)
      if (boxes[f].contains(p)) all.push_back(static_cast<int>(f));
    std::sort(found.begin(), found.end());
    ASSERT_EQ(found, all);
  }
}

constexpr double kThickness = 1e-3, kE = 1e9, kQ = 2000.0;

struct LoopRun {
  std::vector<StepReport> reports;
  bool completed = false;
  NodePositions x;
};

LoopRun run(Model& m, MechanicalSystem& sys, TimeIntegrator& integrator, double t_end,
            double step) {
  State s = test::state_from(sys, NodePositions::Zero(3, m.num_nodes()));
  sys.start_loads(0, s.u, s.v);
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = t_end, loop.step = step;
  LoopRun out;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        out.reports.push_back(*st.report);
        return true;
      });
  out.completed = r.completed;
  if (!r.completed) std::cout << "not completed: " << r.reason << "\n";
  out.x = m.X + sys.displacements(t_end, s.u);
  return out;
}

void print_residuals(const LoopRun& r) {
  std::cout << "Newton residuals of the last step:";
  for (double v : r.reports.back().residuals) std::cout << " " << v;
  std::cout << "\n";
}

// Two square sheets a x a, the lower one held, the upper one (prestressed, edges held) one
// contact thickness above it, minus `overlap`, its inner nodes pushed down by q h² each.
struct TwoSheets {
  std::unique_ptr<Model> m;
  double load = 0;         ///< the sum of the point loads
  std::vector<int> inner;  ///< the upper sheet's nodes free across the thickness
  int n = 8;
  double a = 0.4;
};

TwoSheets two_sheets(double overlap, int relax_steps) {
  TwoSheets ts;
  ts.m = std::make_unique<Model>();
  Model& m = *ts.m;
  const double h = ts.a / ts.n, z = kThickness - overlap;
  for (int layer = 0; layer < 2; ++layer) {
    test::NodeCache nodes(m, 1e-9);
    std::vector<int> conn;
    test::mesh_patch(
        nodes, [&](double u, double v) { return Vec3(ts.a * u, ts.a * v, layer * z); }, ts.n, ts.n,
        "quad4", conn);
    const double S = layer ? 1000.0 / kThickness : 0.0;
    test::add_membrane(
        m, "quad4", std::move(conn),
        SheetLaw(PlaneStressLaw::isotropic("iso", kE, 0.3)).with_prestress({S, S, 0}), 1000.0,
        kThickness);
  }
  std::vector<int> held, inner;
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Vec3 X = m.X.col(i);
    const bool edge = X.x() < 1e-9 || X.y() < 1e-9 || X.x() > ts.a - 1e-9 || X.y() > ts.a - 1e-9;
    if (X.z() < 0.5 * z || edge)
      held.push_back(i);
    else
      inner.push_back(i);
  }
  m.fixed.push_back({held, {true, true, true}});
  m.fixed.push_back({inner, {true, true, false}});
  for (int i : inner) m.point_loads.push_back({{i}, Vec3(0, 0, -kQ * h * h), -1});
  ts.load = kQ * h * h * static_cast<double>(inner.size());
  ts.inner = inner;
  ContactLoad cl;
  cl.parts.push_back({1, {}});
  cl.other.push_back({0, {}});
  for (int e = 0; e < m.blocks[0]->size(); ++e)
    cl.parts[0].elements.push_back(e), cl.other[0].elements.push_back(e);
  cl.relax_steps = relax_steps;
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  return ts;
}

TEST(SheetContact, TwoSheetsPressedTogetherBalanceAndStayApart) {
  TwoSheets ts = two_sheets(0.0, 0);
  MechanicalSystem sys(*ts.m);
  StaticNewton integrator;
  const LoopRun r = run(*ts.m, sys, integrator, 1, 0.25);
  ASSERT_TRUE(r.completed);
  print_residuals(r);
  const double Fz = *sys.loads().back()->quantity_at("contact_force:contact=0:2", 1, r.x);
  const std::vector<double> g = sys.load_node_field("contact_gap", 1, r.x);
  const std::vector<double> q = sys.load_node_field("contact_pressure", 1, r.x);
  double least = 0, qmid = 0;
  for (int n = 0; n < ts.m->num_nodes(); ++n)
    if (!std::isnan(g[static_cast<size_t>(n)])) least = std::min(least, g[static_cast<size_t>(n)]);
  const int mid = test::nearest_node(*ts.m, Vec3(0.2, 0.2, kThickness));
  qmid = q[static_cast<size_t>(mid)];

  const double tol = std::max(0.01 * kThickness, 1e-3 * ts.a / ts.n);
  std::cout << "two sheets: contact force " << Fz << " against the load " << -ts.load << " ("
            << test::percent(Fz, -ts.load) << "%), least gap " << least << " (tolerance " << tol
            << "), pressure at the middle " << qmid << " (load " << kQ << ")\n";
  EXPECT_LT(test::percent(Fz, -ts.load), 0.5);
  EXPECT_GT(least, -tol);
  EXPECT_LT(test::percent(qmid, kQ), 5.0);
  EXPECT_LE(r.reports.back().iterations, 4);
  // The contact area: the upper sheet's nodes that touch, at least the loaded inner nodes'
  // areas (h² each), at most the whole sheet; every inner node in contact.
  const double area = *sys.loads().back()->quantity_at("contact_area:contact=0", 1, r.x);
  const double h = ts.a / ts.n;
  std::cout << "contact area " << area << " (inner nodes " << h * h * ts.inner.size() << ", sheet "
            << ts.a * ts.a << ")\n";
  EXPECT_GE(area, h * h * static_cast<double>(ts.inner.size()) * (1 - 1e-9));
  EXPECT_LE(area, ts.a * ts.a * (1 + 1e-9));
  const std::vector<double> st = sys.load_node_field("contact_status", 1, r.x);
  for (int n : ts.inner) EXPECT_EQ(st[static_cast<size_t>(n)], 2.0);
  // The account: the last accepted step's penetration ratio, and the largest over the four
  // steps, at least that, at an accepted step's time.
  const std::string account = sys.loads().back()->account_json();
  auto number = [&](const std::string& key) {
    const size_t at = account.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(account.substr(at + key.size() + 4));
  };
  const double last = number("max_penetration_ratio"), peak = number("peak_penetration_ratio"),
               when = number("peak_penetration_time");
  EXPECT_GT(last, 0) << account;
  EXPECT_GE(peak, last) << account;
  EXPECT_TRUE(when == 0.25 || when == 0.5 || when == 0.75 || when == 1.0) << account;
}

// The term in a system: K and its low-rank part against central differences of its forces.
void check_term_matrix(Model& m, double scale, const char* what) {
  MechanicalSystem sys(m);
  const int n = sys.size();
  std::srand(5);
  const VecX u0 = scale * VecX::Random(n);
  sys.start_loads(0, u0, VecX::Zero(n));
  MatX J;
  const VecX f = term_forces(sys, kLastTerm, u0, &J);
  ASSERT_GT(f.norm(), 0);
  const double err = term_matrix_error(sys, kLastTerm, u0, J, 1e-9);
  std::cout << what << ": relative error " << err << "\n";
  EXPECT_LT(err, 1e-5) << what;
}

struct Fold;
Fold fold(double c);

TEST(SheetContact, TermMatrixMatchesFiniteDifferences) {
  TwoSheets ts = two_sheets(2e-4, 0);
  check_term_matrix(*ts.m, 1e-4, "two sheets");
}

// The whole system's Jacobian (the sheets' anisotropic membranes and the contact's node
// blocks, scattered pair by pair: subtract_node_blocks) against central differences of its
// residual: two prestressed anisotropic sheets pressed into each other, both free inside
// their edges, the upper one shifted half an element along x and 0.15 of one along y so its
// nodes fall inside the lower one's faces, and the lower sheet's side x = 0 on a skew plane
// (its nodes in a frame of their own: the pair scatter's slow way, for the pairs of the
// faces along that side).
TEST(SheetContact, WholeJacobianOnAnisotropicSheetsMatchesFiniteDifferences) {
  auto m = std::make_unique<Model>();
  const int n = 4;
  const double a = 0.4, h = a / n, overlap = 2e-4;
  AnisotropicConstants ac;
  ac.E1 = 2e9, ac.E2 = 0.8e9, ac.nu12 = 0.3, ac.G12 = 0.5e9, ac.eta1 = 0.2, ac.eta2 = -0.1;
  const SheetLaw law =
      SheetLaw(PlaneStressLaw::anisotropic("aniso", ac)).with_prestress({1e6, 7e5, 2e5});
  for (int layer = 0; layer < 2; ++layer) {
    test::NodeCache nodes(*m, 1e-9);
    std::vector<int> conn;
    const double shift = layer ? 0.5 * h : 0.0;
    test::mesh_patch(
        nodes,
        [&](double u, double v) {
          return Vec3(a * u + shift, a * v + 0.3 * shift, layer * (kThickness - overlap));
        },
        n, n, "quad4", conn);
    test::add_membrane(*m, "quad4", std::move(conn), law, 1000.0, kThickness);
  }
  std::vector<int> held, skew;
  for (int i = 0; i < m->num_nodes(); ++i) {
    const Vec3 X = m->X.col(i);
    const bool lower = X.z() < 0.5 * kThickness;
    const double x0 = lower ? 0.0 : 0.5 * h, y0 = lower ? 0.0 : 0.15 * h;
    const bool at_x0 = X.x() < x0 + 1e-9, at_y0 = X.y() < y0 + 1e-9;
    const bool at_x1 = X.x() > x0 + a - 1e-9, at_y1 = X.y() > y0 + a - 1e-9;
    if (lower && at_x0 && !at_y0 && !at_y1)
      skew.push_back(i);
    else if (at_x0 || at_y0 || at_x1 || at_y1)
      held.push_back(i);
  }
  m->fixed.push_back({held, {true, true, true}});
  m->symmetry.push_back({skew, Vec3(std::cos(0.5), std::sin(0.5), 0)});
  ContactLoad cl;
  cl.parts.push_back({1, {}});
  cl.other.push_back({0, {}});
  for (int e = 0; e < m->blocks[0]->size(); ++e)
    cl.parts[0].elements.push_back(e), cl.other[0].elements.push_back(e);
  m->loads.add(make_load(cl));
  for (auto& l : m->loads) l->set_up(*m);
  MechanicalSystem sys(*m);
  const int neq = sys.size();
  std::srand(3);
  const VecX u0 = 1e-5 * VecX::Random(neq), zero = VecX::Zero(neq);
  sys.start_loads(0, u0, zero);
  VecX r;
  SparseMatrix J;
  sys.evaluate(0, u0, zero, zero, 1, 0, 0, r, &J);
  sys.evaluate(0, u0, zero, zero, 1, 0, 0, r, &J);  // on the pattern with the couplings
  const MatX Jd = MatX(J);
  MatX fd(neq, neq);
  const double step = 1e-9;
  for (int k = 0; k < neq; ++k) {
    VecX up = u0, um = u0, rp, rm;
    up[k] += step, um[k] -= step;
    sys.evaluate(0, up, zero, zero, 1, 0, 0, rp, nullptr);
    sys.evaluate(0, um, zero, zero, 1, 0, 0, rm, nullptr);
    fd.col(k) = (rp - rm) / (2 * step);
  }
  const double err = (Jd - fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
  std::cout << "anisotropic sheets in contact, " << neq << " equations: Jacobian against central "
            << "differences " << err << "\n";
  EXPECT_GT(term_forces(sys, kLastTerm, u0, nullptr).norm(), 1.0);  // the sheets press
  EXPECT_LT(err, 1e-6);
}

// The skin 0.5 mm (the least contact thickness): moves of 0.2 mm reuse the candidates.
TEST(SheetContact, ReusedCandidatesGiveAFreshSearchsForcesAndMatrix) {
  TwoSheets ts = two_sheets(2e-4, 0);
  test::check_reused_candidates(*ts.m, 2e-4, 2e-3, "two sheets");
}

TEST(SheetContact, InitialPenetrationsAreReportedAndRelaxed) {
  // The upper sheet starts 0.3 mm into the lower one's contact thickness.
  std::vector<double> first_residual;
  for (int relax : {0, 4}) {
    TwoSheets ts = two_sheets(3e-4, relax);
    MechanicalSystem sys(*ts.m);
    StaticNewton integrator;
    const LoopRun r = run(*ts.m, sys, integrator, 1, 0.125);
    ASSERT_TRUE(r.completed);
    first_residual.push_back(r.reports.front().residuals.front());
    std::vector<std::string> warnings;
    for (const auto& term : sys.loads())
      term->end_check([&](std::string w) { warnings.push_back(w); });
    ASSERT_FALSE(warnings.empty());
    std::cout << "relax " << relax << ": " << warnings.front() << "; first residual "
              << first_residual.back() << "\n";
    EXPECT_NE(warnings.front().find("initial penetrations, the deepest 0.0003"), std::string::npos);
    // Relaxed or not, the free nodes end apart within the tolerance (the held edges stay
    // where they were put).
    const std::vector<double> g = sys.load_node_field("contact_gap", 1, r.x);
    double least = 0;
    for (int n : ts.inner) least = std::min(least, g[static_cast<size_t>(n)]);
    EXPECT_GT(least, -std::max(0.01 * kThickness, 1e-3 * ts.a / ts.n)) << "relax " << relax;
  }
  // Relaxed, the first step starts from a small force instead of the whole overlap's.
  EXPECT_LT(first_residual[1], 0.5 * first_residual[0]);
}

// A checkpoint taken while initial penetrations are being relaxed carries their offsets: a
// system restored from it has the forces of the one that saved it (not the whole overlap's).
TEST(SheetContact, RelaxationOffsetsGoThroughTheSavedState) {
  TwoSheets ts = two_sheets(3e-4, 4);
  MechanicalSystem a(*ts.m), b(*ts.m);
  const VecX zero = VecX::Zero(a.size());
  VecX ra, rb;
  residuals_after_restore(a, b, ra, rb);
  ASSERT_GT(ra.norm(), 0);
  EXPECT_LT((ra - rb).norm(), 1e-12 * ra.norm());
  // One accepted step later (a quarter of the offsets relaxed more): the restored system
  // counts the steps from the same place.
  {
    MechanicalSystem a1(*ts.m), b1(*ts.m);
    VecX ra1, rb1;
    residuals_after_restore(a1, b1, ra1, rb1, 1);
    EXPECT_GT((ra1 - ra).norm(), 1e-3 * ra.norm());  // the step moved the offsets
    EXPECT_LT((ra1 - rb1).norm(), 1e-12 * ra1.norm());
  }
  // Pushed out at once, the same overlap gives a larger force: the offsets matter here.
  TwoSheets at_once = two_sheets(3e-4, 0);
  MechanicalSystem c(*at_once.m);
  c.start_loads(0.0, zero, zero);
  VecX rc;
  c.evaluate(0.0, zero, zero, zero, 1, 0, 0, rc, nullptr);
  EXPECT_GT(rc.norm(), 1.5 * ra.norm());
}

// A strip folded onto itself: the lower layer and the bend held, the upper layer's nodes free
// to move across the thickness and pushed onto the lower layer by q h² each.
struct Fold {
  std::unique_ptr<Model> m;
  double load = 0;
  std::vector<int> upper;
};

Fold fold(double c) {
  Fold f;
  f.m = std::make_unique<Model>();
  Model& m = *f.m;
  const double L = 0.3, W = 0.1, R = c;  // middle surfaces 2R apart: touching
  const double len = 2 * L + M_PI * R;
  const int nu = 40, nv = 5;
  test::NodeCache nodes(m, 1e-9);
  std::vector<int> conn;
  test::mesh_patch(
      nodes,
      [&](double u, double v) {
        const double s = u * len, y = W * v;
        if (s <= L) return Vec3(s, y, 0);
        if (s >= L + M_PI * R) return Vec3(L - (s - L - M_PI * R), y, 2 * R);
        const double phi = (s - L) / R;
        return Vec3(L + R * std::sin(phi), y, R - R * std::cos(phi));
      },
      nu, nv, "quad4", conn);
  const double S = 100.0 / kThickness;  // a light prestress: the free layer is not a mechanism
  test::add_membrane(m, "quad4", std::move(conn),
                     SheetLaw(PlaneStressLaw::isotropic("iso", kE, 0.3)).with_prestress({S, S, 0}),
                     1000.0, kThickness);
  std::vector<int> held, free;
  const double h = len / nu;
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Vec3 X = m.X.col(i);
    if (X.z() < R || X.x() > L - 1.5 * h)
      held.push_back(i);
    else
      free.push_back(i);
  }
  m.fixed.push_back({held, {true, true, true}});
  m.fixed.push_back({free, {true, true, false}});
  const double hv = W / nv;
  for (int i : free) {
    const Vec3 X = m.X.col(i);
    const double wy = (X.y() < 1e-9 || X.y() > W - 1e-9) ? 0.5 : 1.0;
    const double wx = X.x() < 1e-9 ? 0.5 : 1.0;
    m.point_loads.push_back({{i}, Vec3(0, 0, -kQ * h * hv * wx * wy), -1});
    f.load += kQ * h * hv * wx * wy;
  }
  f.upper = free;
  ContactLoad cl;
  cl.self = true;
  cl.thickness = c;
  cl.parts.push_back({0, {}});
  for (int e = 0; e < m.blocks[0]->size(); ++e) cl.parts[0].elements.push_back(e);
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  return f;
}

void check_fold(const Fold& f, MechanicalSystem& sys, const LoopRun& r, double c) {
  const double Fz = *sys.loads().back()->quantity_at("contact_force:contact=0:2", 1, r.x);
  // Every upper node above the lower layer by the contact distance, within the tolerance.
  double least = 1;
  for (int n : f.upper) least = std::min(least, r.x(2, n) - 2 * c);
  const double tol = std::max(0.01 * 2 * c, 1e-3 * 0.02);
  std::cout << "fold: contact force " << Fz << " against the load " << f.load << " ("
            << test::percent(Fz, f.load) << "%), least gap of the upper layer " << least
            << " (tolerance " << tol << ")\n";
  EXPECT_GT(least, -tol);
  EXPECT_LT(test::percent(Fz, f.load), 1.0);
}

TEST(SheetContact, SelfTermMatrixMatchesFiniteDifferences) {
  Fold f = fold(0.01);
  check_term_matrix(*f.m, 1e-4, "fold (self)");
}

// The skin 1.8 mm (a tenth of the elements' size): moves of 0.8 mm reuse the candidates.
TEST(SheetContact, SelfReusedCandidatesGiveAFreshSearchsForcesAndMatrix) {
  Fold f = fold(0.01);
  test::check_reused_candidates(*f.m, 8e-4, 5e-3, "fold (self)");
}

TEST(SheetContact, FoldedSheetKeepsItsLayersApartStatic) {
  const double c = 0.01;
  Fold f = fold(c);
  MechanicalSystem sys(*f.m);
  StaticNewton integrator;
  const LoopRun r = run(*f.m, sys, integrator, 1, 0.5);
  ASSERT_TRUE(r.completed);
  print_residuals(r);
  check_fold(f, sys, r, c);
}

TEST(SheetContact, FoldedSheetKeepsItsLayersApartDynamic) {
  const double c = 0.01;
  Fold f = fold(c);
  MechanicalSystem sys(*f.m);
  auto integrator = GeneralizedAlpha::chung_hulbert(0.8);
  const LoopRun r = run(*f.m, sys, *integrator, 0.02, 0.002);
  ASSERT_TRUE(r.completed);
  print_residuals(r);
  double least = 1;
  for (int n : f.upper) least = std::min(least, r.x(2, n) - 2 * c);
  std::cout << "fold, dynamic: least gap of the upper layer " << least << "\n";
  EXPECT_GT(least, -std::max(0.01 * 2 * c, 1e-3 * 0.02));
}

}  // namespace
}  // namespace velum
