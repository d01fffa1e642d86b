// Geodesics on triangulated surfaces and seams cut along them (issue 45): on a plate the
// straight segment, on a cylinder the unrolled straight line (the helix to the chord error), on
// a sphere the great-circle arc to an error that falls under refinement; seams part a plate
// and a hemisphere into panels (gores that flatten as the gore test's).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "velum/analysis/flatten.hpp"
#include "velum/analysis/geodesic.hpp"
#include "velum/analysis/seam_cut.hpp"

namespace velum {
namespace {

struct Mesh {
  NodePositions x;
  std::vector<std::array<int, 3>> tris;
};

// (nu x nv) cells of f(s, t), s, t in [0, 1], two triangles each; `ring`: s = 1 is s = 0.
Mesh surface_grid(int nu, int nv, const std::function<Vec3(double, double)>& f, bool ring = false) {
  Mesh m;
  const int cols = ring ? nu : nu + 1;
  m.x.resize(3, cols * (nv + 1));
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < cols; ++i) m.x.col(j * cols + i) = f(double(i) / nu, double(j) / nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * cols + i, b = j * cols + (i + 1) % cols, c = b + cols, d = a + cols;
      m.tris.push_back({a, b, c});
      m.tris.push_back({a, c, d});
    }
  return m;
}

SurfacePoint vertex(int v) {
  SurfacePoint p;
  p.vertex = v;
  return p;
}

// The length of a path from its points' positions (each piece straight in a triangle).
double polyline_length(const TriangleSurface& s, const SurfacePath& p) {
  double L = 0;
  for (size_t k = 0; k + 1 < p.points.size(); ++k)
    L += (s.position(p.points[k + 1]) - s.position(p.points[k])).norm();
  return L;
}

TEST(Geodesic, StraightSegmentOnAPlate) {
  // An irregular plate: interior nodes moved in the plane.
  Mesh m = surface_grid(12, 9, [](double s, double t) {
    const double ds = (s > 0 && s < 1 && t > 0 && t < 1) ? 0.02 * std::sin(37 * s + 11 * t) : 0;
    const double dt = (s > 0 && s < 1 && t > 0 && t < 1) ? 0.02 * std::cos(23 * s - 7 * t) : 0;
    return Vec3(1.2 * s + ds, 0.9 * t + dt, 0.0);
  });
  const TriangleSurface s(m.x, m.tris);
  for (const auto& [a, b] : {std::pair{Vec3(0.03, 0.11, 0), Vec3(1.13, 0.77, 0)},
                             std::pair{Vec3(0.0, 0.45, 0), Vec3(1.2, 0.3, 0)},
                             std::pair{Vec3(0.6, 0.0, 0), Vec3(0.55, 0.9, 0)}}) {
    double d = 0;
    const auto from = locate(s, a, 0, &d), to = locate(s, b, 0, &d);
    const SurfacePath p = geodesic(s, from, to);
    EXPECT_NEAR(p.length, (b - a).norm(), 1e-12);
    EXPECT_NEAR(polyline_length(s, p), (b - a).norm(), 1e-12);
    for (const auto& q : p.points)  // every point on the segment
      EXPECT_LT((s.position(q) - a).cross(b - a).norm() / (b - a).norm(), 1e-12);
  }
}

TEST(Geodesic, HelixOnACylinder) {
  // A closed ring of 48 facets: the polyhedral cylinder unrolls into a strip 48 chords wide, so
  // the geodesic between two nodes is the straight line there; against the helix on the round
  // cylinder the chord shortens the turn by at most R dphi (delta^2 / 24), delta = 2 pi / 48.
  const double R = 1.5, H = 4.0;
  const int nu = 48, nv = 20;
  const Mesh m = surface_grid(
      nu, nv,
      [&](double s, double t) {
        return Vec3(R * std::cos(2 * M_PI * s), R * std::sin(2 * M_PI * s), H * t);
      },
      true);
  const TriangleSurface s(m.x, m.tris);
  const double delta = 2 * M_PI / nu, chord = 2 * R * std::sin(delta / 2);
  for (const auto& [i0, j0, i1, j1] :
       {std::array{0, 0, 17, 20}, std::array{40, 3, 10, 15}, std::array{5, 18, 6, 1}}) {
    const int di = std::min(std::abs(i1 - i0), nu - std::abs(i1 - i0));
    const double dz = H * (j1 - j0) / nv;
    const double unrolled = std::hypot(di * chord, dz), helix = std::hypot(R * di * delta, dz);
    const SurfacePath p = geodesic(s, vertex(j0 * nu + i0), vertex(j1 * nu + i1));
    EXPECT_NEAR(p.length, unrolled, 1e-11) << i0 << " " << j0 << " " << i1 << " " << j1;
    EXPECT_NEAR(polyline_length(s, p), unrolled, 1e-11);
    EXPECT_LE(helix - p.length, R * di * delta * delta * delta / 24 + 1e-12);
    EXPECT_GE(helix - p.length, 0);
  }
}

// An icosahedron's faces each cut into n x n, the nodes put on the sphere of radius R.
Mesh icosphere(int n, double R) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  const std::vector<Vec3> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                               {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                               {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const int F[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  Mesh m;
  std::map<std::tuple<long, long, long>, int> index;  // nodes by rounded position
  std::vector<Vec3> pts;
  auto node = [&](const Vec3& p) {
    const Vec3 q = R * p.normalized();
    const auto key = std::make_tuple(std::lround(q.x() * 1e9), std::lround(q.y() * 1e9),
                                     std::lround(q.z() * 1e9));
    auto [it, added] = index.emplace(key, static_cast<int>(pts.size()));
    if (added) pts.push_back(q);
    return it->second;
  };
  for (const auto& f : F) {
    const Vec3 a = v[f[0]], b = v[f[1]], c = v[f[2]];
    auto at = [&](int i, int j) {
      return node(a + (b - a) * i / double(n) + (c - a) * j / double(n));
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        m.tris.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
        if (i + j + 1 < n) m.tris.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  }
  m.x.resize(3, static_cast<long>(pts.size()));
  for (size_t k = 0; k < pts.size(); ++k) m.x.col(static_cast<long>(k)) = pts[k];
  return m;
}

TEST(Geodesic, GreatCircleOnASphereConvergesUnderRefinement) {
  const double R = 2.0;
  const Vec3 a = R * Vec3(1, 0.2, 0.3).normalized(), b = R * Vec3(-0.3, 0.9, -0.4).normalized();
  const double arc = R * std::acos(a.dot(b) / (R * R));
  double previous = 0;
  for (int n : {6, 12}) {
    const Mesh m = icosphere(n, R);
    const TriangleSurface s(m.x, m.tris);
    double da = 0, db = 0;
    const SurfacePath p = geodesic(s, locate(s, a, 0, &da), locate(s, b, 0, &db));
    const double error = std::abs(p.length - arc) / arc;
    std::printf(
        "icosphere %d x %d per face: %zu triangles, mean edge %.4f, geodesic %.6f against "
        "the arc %.6f (error %.2e), %d strip moves\n",
        n, n, m.tris.size(), s.mean_edge(), p.length, arc, error, p.flips);
    EXPECT_NEAR(polyline_length(s, p), p.length, 1e-12 * arc);
    // The inscribed polyhedron is shorter by its chords: about (h / R)^2 / 24 with the edge h.
    EXPECT_LT(error, std::pow(s.mean_edge() / R, 2) / 8) << n;
    if (previous > 0) {
      EXPECT_LT(error, previous / 3) << "halving the edges";
    }
    previous = error;
    EXPECT_GT(p.flips, 0);  // the edge path was not already straight
  }
}

TEST(Seams, ChordAcrossAPlateSplitsTrianglesIntoTwoPanels) {
  const Mesh m = surface_grid(6, 4, [](double s, double t) { return Vec3(3 * s, 2 * t, 0); });
  const Vec3 a(0.0, 0.37, 0), b(3.0, 1.71, 0);
  const double below = 3 * (a.y() + b.y()) / 2, h = std::hypot(0.5, 0.5);
  for (double snap : {0.0, 0.2}) {
    SeamCutter cut(m.x, m.tris, snap);
    double d = 0;
    const auto from = locate(cut.surface(), a, 1e-9, &d), to = locate(cut.surface(), b, 1e-9, &d);
    ASSERT_EQ(from.kind, SurfacePoint::Kind::Edge);
    cut.add_geodesic(from, to, 0);
    int count = 0;
    const auto panel = cut.panels(&count);
    ASSERT_EQ(count, 2);
    // Areas of the two parts against the trapezoids either side of the chord: exact when the
    // seam is cut where it crosses; moved to corners within snap h, by at most snap h its length.
    double area[2] = {0, 0};
    const auto& x = cut.surface().x();
    ASSERT_EQ(panel.size(), cut.triangles().size());
    for (size_t f = 0; f < panel.size(); ++f) {
      const auto& t = cut.triangles()[f];
      area[panel[f]] += 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
    }
    EXPECT_NEAR(area[0] + area[1], 6.0, 1e-12);
    EXPECT_NEAR(std::min(area[0], area[1]), std::min(below, 6 - below),
                snap > 0 ? snap * h * (b - a).norm() : 1e-12);
    EXPECT_GT(cut.new_nodes().size(), 0u);
    std::printf(
        "snap %.1f: %zu new nodes, smallest angle of a split triangle %.1f deg, area %.6f "
        "against %.6f\n",
        snap, cut.new_nodes().size(), cut.smallest_new_angle() * 180 / M_PI,
        std::min(area[0], area[1]), std::min(below, 6 - below));
    // Crossings within a fifth of an edge from a corner go through it: no sliver triangles.
    if (snap > 0) {
      EXPECT_GT(cut.smallest_new_angle(), 5.0 * M_PI / 180);
    }
  }
}

TEST(Seams, ASeamEndingInsideAPanelIsRefused) {
  const Mesh m = surface_grid(6, 4, [](double s, double t) { return Vec3(3 * s, 2 * t, 0); });
  SeamCutter cut(m.x, m.tris);
  cut.add_node_path({0, 8, 16}, 0);  // from the corner inwards, stopping inside
  int count = 0;
  EXPECT_THROW(cut.panels(&count), SeamError);
  EXPECT_THROW(cut.add_node_path({0, 20}, 1), SeamError);  // not joined by an edge
}

TEST(Seams, HemisphereCutIntoGoresAlongMeridians) {
  // A hemisphere of (6 N) x 24 cells, its pole one node; N geodesic seams from the equator to
  // the pole give N gores, each flattening pi R / 2 long and 2 pi R / N wide as the gore test's.
  const double R = 1.5;
  for (int N : {12, 16}) {
    const int nu = 6 * N, nv = 24;
    Mesh g = surface_grid(
        nu, nv,
        [&](double s, double t) {
          const double phi = 2 * M_PI * s, theta = M_PI / 2 * t;
          return Vec3(R * std::cos(theta) * std::cos(phi), R * std::cos(theta) * std::sin(phi),
                      R * std::sin(theta));
        },
        true);
    const int pole = nv * nu;
    Mesh m;
    m.x = g.x.leftCols(pole + 1);
    m.x.col(pole) = Vec3(0, 0, R);
    for (auto t : g.tris) {
      for (int& n : t) n = std::min(n, pole);
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) m.tris.push_back(t);
    }
    SeamCutter cut(m.x, m.tris);
    for (int k = 0; k < N; ++k) {
      // The seam's equator end given as a point, its pole end as a point: both snap to nodes.
      const double phi = 2 * M_PI * k / N;
      double d = 0;
      const auto from =
          locate(cut.surface(), Vec3(R * std::cos(phi), R * std::sin(phi), 0), 1e-6, &d);
      const auto to = locate(cut.surface(), Vec3(0, 0, R), 1e-6, &d);
      cut.add_geodesic(from, to, k);
    }
    int count = 0;
    const auto panel = cut.panels(&count);
    ASSERT_EQ(count, N);
    // The seams follow the meridian mesh lines but near the pole (where the cells are thin).
    std::printf("%d gores: %zu new nodes, smallest new angle %.1f deg\n", N, cut.new_nodes().size(),
                cut.smallest_new_angle() * 180 / M_PI);
    for (int gore = 0; gore < N; ++gore) {
      PanelMesh pm;
      for (size_t f = 0; f < panel.size(); ++f)
        if (panel[f] == gore) pm.triangles.push_back(cut.triangles()[f]);
      const FlatPanel p = flatten_panel(cut.surface().x(), pm);
      auto local = [&](int node) {
        for (size_t k = 0; k < p.nodes.size(); ++k)
          if (p.nodes[k] == node) return static_cast<int>(k);
        return -1;
      };
      // The gore's equator nodes and its centre line.
      int lo = nu, hi = -1;
      for (int n : p.nodes)
        if (n < nu) lo = std::min(lo, n), hi = std::max(hi, n);
      if (hi - lo > nu / 2) {  // the gore across phi = 0
        lo = nu, hi = -1;
        for (int n : p.nodes)
          if (n < nu) (n > nu / 2 ? lo : hi) = n > nu / 2 ? std::min(lo, n) : std::max(hi, n);
        hi += nu;
      }
      double width = 0, length = 0;
      for (int i = lo; i < hi; ++i)
        width += (p.uv[local(i % nu)] - p.uv[local((i + 1) % nu)]).norm();
      const int mid = ((lo + hi) / 2) % nu;
      for (int j = 0; j < nv; ++j) {
        const int a = j * nu + mid, b = j + 1 == nv ? pole : (j + 1) * nu + mid;
        length += (p.uv[local(a)] - p.uv[local(b)]).norm();
      }
      const double L = M_PI * R / 2, W = 2 * M_PI * R / N;
      EXPECT_NEAR(length, L, 0.005 * L) << N << " gores, gore " << gore;
      EXPECT_NEAR(width, W, 0.01 * W) << N << " gores, gore " << gore;
    }
  }
}

}  // namespace
}  // namespace velum
