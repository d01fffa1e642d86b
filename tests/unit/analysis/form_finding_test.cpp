// Form finding by the updated reference strategy (analysis/form_finding.hpp): the soap-film
// catenoid, an anisotropic prestress whose shape depends on warp/fill, and a four-point sail
// with edge cables whose cable force and fabric prestress must balance at every edge node.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "velum/analysis/form_finding.hpp"

namespace velum {
namespace {

const double kPi = std::acos(-1.0);

// A structured quad4 grid of (nu + 1) x (nv + 1) nodes placed by `at(i, j)`; `wrap` joins
// column nu - 1 to column 0 (a ring) instead of adding column nu.
template <class At>
std::vector<int> quad_grid(Model& m, int nu, int nv, bool wrap, const At& at) {
  const int cols = wrap ? nu : nu + 1;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < cols; ++i) m.add_node(1 + j * cols + i, at(i, j));
  std::vector<int> conn;
  auto id = [&](int i, int j) { return j * cols + (wrap ? i % nu : i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      for (int n : {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)}) conn.push_back(n);
  return conn;
}

void add_sheet(Model& m, std::vector<int> conn, const Vec3& prestress) {
  BlockSetupReport report;
  const SheetLaw law =
      SheetLaw(PlaneStressLaw::isotropic("film", 1.0, 0.0)).with_prestress(prestress);
  m.blocks.push_back(make_membrane_block("quad4", "film", std::move(conn), m.X, law, 1.0, 1.0,
                                         nullptr, shape::Integration::kGauss, report));
}

// Tolerance 1e-4: on a curved sheet the residual falls to a few 1e-5 of the force scale in a
// dozen updates and then creeps (the mesh sliding along the found surface, which an isotropic
// stress does not resist; the shape no longer changes).
AnalysisSettings form_finding_settings(double tolerance = 1e-4) {
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kFormFinding;
  s.time.t_end = 1, s.time.step = 1;
  s.form_finding.tolerance = tolerance;
  s.form_finding.max_updates = 100;
  return s;
}

// The soap film between two coaxial rings of radius R a distance 2h apart is the catenoid
// r = a cosh(z / a), with a cosh(h / a) = R; of the two roots the larger (the stable one).
// From the cylinder r = R, with an isotropic prestress.
TEST(FormFinding, SoapFilmCatenoidNeckRadius) {
  const double R = 1, h = 0.5;
  // Stable root of a cosh(h/a) = R by bisection on [h / 1.2, R] (1.2: the extremum of
  // cosh(u)/u, u = h/a, lies at u ≈ 1.1997; the stable root has u below it).
  double lo = h / 1.1997, hi = R;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mid * std::cosh(h / mid) - R > 0 ? hi : lo) = mid;
  }
  const double a = 0.5 * (lo + hi);
  const int nt = 48, nz = 16;
  Model m;
  auto conn = quad_grid(m, nt, nz, true, [&](int i, int j) {
    const double th = 2 * kPi * i / nt;
    return Vec3(R * std::cos(th), R * std::sin(th), -h + 2 * h * j / nz);
  });
  add_sheet(m, conn, Vec3(1, 1, 0));
  FixedDofs rings;
  rings.fix = {true, true, true};
  for (int i = 0; i < nt; ++i) rings.nodes.push_back(i), rings.nodes.push_back(nz * nt + i);
  m.fixed.push_back(rings);
  MechanicalSystem view(m);
  FormFindingReport rep;
  const AnalysisResult res = run_form_finding(m, view, form_finding_settings(), {}, {}, &rep);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  double neck = 0;
  for (int i = 0; i < nt; ++i) neck += rep.shape.col(nz / 2 * nt + i).head<2>().norm() / nt;
  const double err = neck / a - 1;
  std::cout << "catenoid R = " << R << ", h = " << h << ": neck " << neck << ", a = " << a
            << ", error " << 100 * err << "% after " << rep.updates << " updates (residual "
            << rep.residual << ")\n";
  EXPECT_LT(std::abs(err), 5e-3);
  EXPECT_LT(rep.residual, 1e-4);
  // On the found shape the sheet carries the prestress as its true stress (to the accuracy of
  // the centre output of a warped quad4, which uses its nearest Gauss point's frame: 3%).
  const ElementOutput out = m.blocks[0]->output(0, rep.shape);
  EXPECT_NEAR(out.stress.max, 1.0, 0.05);
  EXPECT_NEAR(out.stress.min, 1.0, 0.05);
}

// Warp ≠ fill: a sheet over the square 0 <= x, y <= 1 held at w = A sin(πx) on the edges
// y = 0 and y = 1 and at w = 0 on x = 0 and x = 1, with the prestress Nx along x (the sheet's
// warp, the default axes) and Ny along y. For small slopes Nx w,xx + Ny w,yy = 0, so
// w = A sin(πx) cosh(k (y − ½)) / cosh(k / 2) with k = π sqrt(Nx / Ny): the centre rises to
// A / cosh(k / 2), 0.087 A for Nx = 4 Ny and 0.755 A for Ny = 4 Nx (0.398 A isotropic).
TEST(FormFinding, AnisotropicPrestressSetsTheShape) {
  const double A = 0.02;
  const int n = 24;
  for (const Vec3& S0 : {Vec3(4, 1, 0), Vec3(1, 4, 0)}) {
    Model m;
    auto conn = quad_grid(m, n, n, false, [&](int i, int j) {
      const double x = double(i) / n, y = double(j) / n;
      const bool edge_y = j == 0 || j == n;
      return Vec3(x, y, edge_y ? A * std::sin(kPi * x) : 0.0);
    });
    add_sheet(m, conn, S0);
    FixedDofs edges;
    edges.fix = {true, true, true};
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || i == n || j == n) edges.nodes.push_back(j * (n + 1) + i);
    m.fixed.push_back(edges);
    MechanicalSystem view(m);
    FormFindingReport rep;
    // A uniform warp ≠ fill stress on a curved sheet is in in-plane equilibrium only to second
    // order in the slope: the residual levels off at 5.07e-4 of the force scale for 4:1 (the mesh
    // creeping along the surface), the shape settled.
    const AnalysisResult res =
        run_form_finding(m, view, form_finding_settings(5.5e-4), {}, {}, &rep);
    ASSERT_TRUE(res.loop.completed) << res.loop.reason;
    const double k = kPi * std::sqrt(S0[0] / S0[1]);
    const double expected = A / std::cosh(k / 2);
    const double centre = rep.shape(2, n / 2 * (n + 1) + n / 2);
    std::cout << "warp " << S0[0] << ", fill " << S0[1] << ": centre " << centre / A
              << " A, small-slope theory " << expected / A << " A, " << rep.updates
              << " updates, residual " << rep.residual << "\n";
    EXPECT_NEAR(centre, expected, 0.02 * expected);
    // The stress on the found shape is the prescribed one, in warp and fill.
    const ElementOutput out = m.blocks[0]->output(n / 2 * n + n / 2, rep.shape);
    EXPECT_NEAR(out.stress.sheet[0], S0[0], 1e-3 * S0[0]);
    EXPECT_NEAR(out.stress.sheet[1], S0[1], 1e-3 * S0[0]);
  }
}

// A four-point sail (hypar) with edge cables: corners (0,0,0), (L,0,H), (L,L,0), (0,L,H)
// pinned, the other edge nodes held only by cables of force N, the fabric prestressed
// isotropically to n. At every edge node the cable forces balance the fabric's (the
// residual reported), and each edge cable becomes an arc of radius N / n in the fabric's
// tangent plane (the fabric pulls normal to the cable with n per unit length).
TEST(FormFinding, FourPointSailEdgeCablesBalanceThePrestress) {
  const double L = 10, H = 2, nfab = 1.0, N = 20.0;
  const int n = 20;
  Model m;
  auto conn = quad_grid(m, n, n, false, [&](int i, int j) {
    const double u = double(i) / n, v = double(j) / n;
    // Bilinear between the corner heights 0, H, 0, H.
    return Vec3(L * u, L * v, H * (u * (1 - v) + v * (1 - u)));
  });
  add_sheet(m, conn, Vec3(nfab, nfab, 0));
  auto node = [&](int i, int j) { return j * (n + 1) + i; };
  std::vector<int> cable_conn, edge_nodes;
  for (int k = 0; k < n; ++k)
    for (auto [a, b] :
         {std::pair{node(k, 0), node(k + 1, 0)}, std::pair{node(n, k), node(n, k + 1)},
          std::pair{node(k, n), node(k + 1, n)}, std::pair{node(0, k), node(0, k + 1)}})
      cable_conn.push_back(a), cable_conn.push_back(b);
  for (int k = 1; k < n; ++k)
    for (int e : {node(k, 0), node(n, k), node(k, n), node(0, k)}) edge_nodes.push_back(e);
  const double area = 1e-4;
  BlockSetupReport report;
  m.blocks.push_back(make_cable_block("cable2", "edge", cable_conn, m.X,
                                      CableLaw{.E = 1e9, .S0 = N / area}, 1.0, area,
                                      shape::Integration::kGauss, report));
  m.fixed.push_back(
      {.nodes = {node(0, 0), node(n, 0), node(n, n), node(0, n)}, .fix = {true, true, true}});
  MechanicalSystem view(m);
  FormFindingReport rep;
  const AnalysisResult res = run_form_finding(m, view, form_finding_settings(1e-5), {}, {}, &rep);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  // Residual at the edge nodes on the found shape, with the sections set up there.
  Model found;
  for (int k = 0; k < m.num_nodes(); ++k) found.add_node(m.node_ids[k], rep.shape.col(k));
  for (const auto& b : m.blocks) found.blocks.push_back(b->on_reference(rep.shape, 0.0));
  found.fixed = m.fixed;
  MechanicalSystem sys(found);
  const VecX zero = VecX::Zero(sys.size());
  VecX r;
  sys.evaluate(0, zero, zero, zero, 1, 0, 0, r, nullptr);
  double worst = 0;
  for (int e : edge_nodes) {
    Vec3 f = Vec3::Zero();
    for (int c = 0; c < 3; ++c) f[c] = r[sys.dofs().equation(e, c)];
    worst = std::max(worst, f.norm());
  }
  // The arc at the middle of each edge: the circle through three consecutive nodes.
  double worst_radius = 0;
  for (auto mid : {std::array{node(n / 2 - 1, 0), node(n / 2, 0), node(n / 2 + 1, 0)},
                   std::array{node(n, n / 2 - 1), node(n, n / 2), node(n, n / 2 + 1)}}) {
    const Vec3 p = rep.shape.col(mid[0]), q = rep.shape.col(mid[1]), s = rep.shape.col(mid[2]);
    const double a = (q - p).norm(), b = (s - q).norm(), c = (s - p).norm();
    const double radius = a * b * c / (2 * (q - p).cross(s - p).norm());
    worst_radius = std::max(worst_radius, std::abs(radius / (N / nfab) - 1));
  }
  const double sag = (rep.shape.col(node(n / 2, 0)) -
                      0.5 * (rep.shape.col(node(0, 0)) + rep.shape.col(node(n, 0))))
                         .norm();
  std::cout << "four-point sail: " << rep.updates << " updates; largest force left at an edge "
            << "node " << worst << " (" << worst / N << " of the cable force), arc radius off N/n "
            << "by " << 100 * worst_radius << "%, mid-edge sag " << sag << "\n";
  EXPECT_LT(worst, 1e-5 * N);
  EXPECT_LT(worst_radius, 0.02);
}

}  // namespace
}  // namespace velum
