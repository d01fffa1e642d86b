// Seams cut into a triangulated surface, and the panels they part
// (include/velum/analysis/seam_cut.hpp).
#include "velum/analysis/seam_cut.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace velum {
namespace {

uint64_t edge_key(int a, int b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
}

// A convex polygon (corners and points on a triangle's edges, in order round it) cut into
// triangles, each time the ear of largest smallest angle that is a triangle and leaves a
// polygon of three corners or more (points on a straight run are no corners).
void ear_clip(std::vector<int> poly, const NodePositions& x, std::vector<std::array<int, 3>>& out) {
  auto straight = [&](const std::vector<int>& g, size_t i) {
    const int a = g[(i + g.size() - 1) % g.size()], b = g[i], c = g[(i + 1) % g.size()];
    const Vec3 u = x.col(a) - x.col(b), v = x.col(c) - x.col(b);
    return u.cross(v).norm() <= 1e-12 * u.norm() * v.norm();
  };
  while (poly.size() > 3) {
    size_t best = poly.size();
    double best_q = -1;
    for (size_t i = 0; i < poly.size(); ++i) {
      if (straight(poly, i)) continue;
      std::vector<int> rest = poly;
      rest.erase(rest.begin() + static_cast<long>(i));
      int corners = 0;
      for (size_t k = 0; k < rest.size(); ++k) corners += straight(rest, k) ? 0 : 1;
      if (corners < 3) continue;
      const int a = poly[(i + poly.size() - 1) % poly.size()], b = poly[i],
                c = poly[(i + 1) % poly.size()];
      const double q = smallest_angle(x.col(a), x.col(b), x.col(c));
      if (q > best_q) best_q = q, best = i;
    }
    if (best == poly.size()) throw std::logic_error("seam cut: a polygon without an ear");
    out.push_back(
        {poly[(best + poly.size() - 1) % poly.size()], poly[best], poly[(best + 1) % poly.size()]});
    poly.erase(poly.begin() + static_cast<long>(best));
  }
  out.push_back({poly[0], poly[1], poly[2]});
}

}  // namespace

double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  auto angle = [](const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); };
  return std::min({angle(b - a, c - a), angle(a - b, c - b), angle(a - c, b - c)});
}

SeamCutter::SeamCutter(NodePositions x, std::vector<std::array<int, 3>> triangles, double snap)
    : surface_(std::move(x), std::move(triangles)), snap_(snap) {
  original_nodes_ = static_cast<int>(surface_.x().cols());
  fixed_.assign(static_cast<size_t>(original_nodes_), 0);
  parent_.resize(surface_.triangles().size());
  for (size_t f = 0; f < parent_.size(); ++f) parent_[f] = static_cast<int>(f);
  split_.assign(parent_.size(), 0);
}

void SeamCutter::mark(int a, int b, int seam) {
  seam_edges_.emplace(edge_key(a, b), seam);
}

SurfacePath SeamCutter::add_geodesic(const SurfacePoint& from, const SurfacePoint& to, int seam) {
  for (const auto* p : {&from, &to})
    if (p->kind == SurfacePoint::Kind::Face)
      throw SeamError(
          "it ends inside the surface, not on its boundary, on another seam or at a node", seam,
          -1);
  SurfacePath path = geodesic(surface_, from, to);
  cut(path.points, seam);
  return path;
}

void SeamCutter::add_node_path(const std::vector<int>& nodes, int seam) {
  for (size_t k = 0; k + 1 < nodes.size(); ++k) {
    bool joined = false;
    for (int f : surface_.faces_at(nodes[k]))
      joined = joined || has_vertex(surface_.triangles()[static_cast<size_t>(f)], nodes[k + 1]);
    if (!joined)
      throw SeamError("no element edge joins two nodes of the path", seam, nodes[k], nodes[k + 1]);
    mark(nodes[k], nodes[k + 1], seam);
  }
}

void SeamCutter::cut(const std::vector<SurfacePoint>& in, int seam) {
  const TriangleSurface& s = surface_;
  // Crossings close to a corner go through the corner.
  std::vector<SurfacePoint> pts;
  std::map<int, Vec3> onto;  // a corner the seam goes through -> the nearest crossing it snapped
  for (SurfacePoint p : in) {
    if (p.kind == SurfacePoint::Kind::Edge && (p.t <= snap_ || p.t >= 1 - snap_)) {
      const Vec3 at = s.position(p);
      p.vertex = p.t <= snap_ ? p.a : p.b;
      p.kind = SurfacePoint::Kind::Vertex;
      auto [it, added] = onto.emplace(p.vertex, at);
      if (!added && (at - s.x().col(p.vertex)).norm() < (it->second - s.x().col(p.vertex)).norm())
        it->second = at;
    }
    if (!pts.empty() && pts.back().kind == SurfacePoint::Kind::Vertex &&
        p.kind == SurfacePoint::Kind::Vertex && pts.back().vertex == p.vertex)
      continue;
    pts.push_back(p);
  }
  // Nodes for the crossings kept: per edge (min, max) its new nodes by t from min.
  NodePositions x = s.x();
  std::map<uint64_t, std::vector<std::pair<double, int>>> on_edge;
  std::vector<int> node(pts.size(), -1);
  std::vector<Vec3> added;
  for (size_t k = 0; k < pts.size(); ++k) {
    const auto& p = pts[k];
    if (p.kind == SurfacePoint::Kind::Vertex) {
      node[k] = p.vertex;
      continue;
    }
    const double t = p.a < p.b ? p.t : 1 - p.t;
    auto& list = on_edge[edge_key(p.a, p.b)];
    for (const auto& [tt, n] : list)
      if (std::abs(tt - t) < 1e-12) node[k] = n;
    if (node[k] < 0) {
      node[k] = static_cast<int>(x.cols() + static_cast<long>(added.size()));
      list.push_back({t, node[k]});
      new_.push_back({std::min(p.a, p.b), std::max(p.a, p.b), t});
      added.push_back(s.position(p));
    }
  }
  if (!added.empty()) {
    const long n0 = x.cols();
    x.conservativeResize(3, n0 + static_cast<long>(added.size()));
    for (size_t k = 0; k < added.size(); ++k) x.col(n0 + static_cast<long>(k)) = added[k];
  }
  // The seam's pieces: along an edge, or a chord across a triangle.
  std::map<int, std::vector<std::pair<int, int>>> chords;
  std::vector<std::pair<int, int>> along;
  for (size_t k = 0; k + 1 < pts.size(); ++k) {
    const auto &p = pts[k], &q = pts[k + 1];
    const bool pv = p.kind == SurfacePoint::Kind::Vertex, qv = q.kind == SurfacePoint::Kind::Vertex;
    const bool same_edge = (pv && qv) || (pv && (p.vertex == q.a || p.vertex == q.b)) ||
                           (qv && (q.vertex == p.a || q.vertex == p.b)) ||
                           (!pv && !qv && edge_key(p.a, p.b) == edge_key(q.a, q.b));
    if (same_edge) {
      along.push_back({node[k], node[k + 1]});
      continue;
    }
    const auto fp = s.faces_of(p), fq = s.faces_of(q);
    int face = -1;
    for (int f : fp)
      if (std::find(fq.begin(), fq.end(), f) != fq.end()) face = f;
    if (face < 0) throw std::logic_error("seam cut: two points of the path share no triangle");
    chords[face].push_back({node[k], node[k + 1]});
  }
  // Triangles with a new node on an edge or a chord across are cut.
  std::vector<std::array<int, 3>> tris;
  std::vector<int> parent;
  std::vector<char> split;
  for (size_t f = 0; f < s.triangles().size(); ++f) {
    const auto& t = s.triangles()[f];
    auto ch = chords.find(static_cast<int>(f));
    bool touched = ch != chords.end();
    for (int k = 0; k < 3 && !touched; ++k)
      touched = on_edge.count(edge_key(t[k], t[(k + 1) % 3])) > 0;
    if (!touched) {
      tris.push_back(t), parent.push_back(parent_[f]), split.push_back(split_[f]);
      continue;
    }
    std::vector<int> poly;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      poly.push_back(a);
      if (auto it = on_edge.find(edge_key(a, b)); it != on_edge.end()) {
        auto list = it->second;
        std::sort(list.begin(), list.end());
        if (a > b) std::reverse(list.begin(), list.end());
        for (const auto& [tt, n] : list) poly.push_back(n);
      }
    }
    std::vector<std::vector<int>> pieces{poly};
    if (ch != chords.end())
      for (const auto& [p, q] : ch->second)
        for (size_t i = 0; i < pieces.size(); ++i) {
          auto& g = pieces[i];
          auto ip = std::find(g.begin(), g.end(), p), iq = std::find(g.begin(), g.end(), q);
          if (ip == g.end() || iq == g.end()) continue;
          size_t a = static_cast<size_t>(ip - g.begin()), b = static_cast<size_t>(iq - g.begin());
          if (a > b) std::swap(a, b);
          if (b - a == 1 || (a == 0 && b + 1 == g.size())) break;  // along a side
          std::vector<int> one(g.begin() + static_cast<long>(a),
                               g.begin() + static_cast<long>(b) + 1);
          std::vector<int> two(g.begin() + static_cast<long>(b), g.end());
          two.insert(two.end(), g.begin(), g.begin() + static_cast<long>(a) + 1);
          g = one;
          pieces.push_back(two);
          break;
        }
    for (const auto& g : pieces) {
      const size_t before = tris.size();
      ear_clip(g, x, tris);
      parent.resize(tris.size(), parent_[f]);
      split.resize(tris.size(), 1);
      (void)before;
    }
  }
  // Seam edges split by the new nodes go on as their pieces.
  for (const auto& [key, list] : on_edge) {
    auto it = seam_edges_.find(key);
    if (it == seam_edges_.end()) continue;
    const int old = it->second;
    seam_edges_.erase(it);
    auto sorted = list;
    std::sort(sorted.begin(), sorted.end());
    int prev = static_cast<int>(key >> 32);
    for (const auto& [tt, n] : sorted) mark(prev, n, old), prev = n;
    mark(prev, static_cast<int>(key & 0xffffffffu), old);
  }
  for (const auto& [p, q] : along) {
    // Along an edge that now has new nodes on it: its pieces between p and q.
    const uint64_t key = edge_key(p, q);
    mark(p, q, seam);
    (void)key;
  }
  for (const auto& [f, list] : chords)
    for (const auto& [p, q] : list) mark(p, q, seam);
  surface_ = TriangleSurface(std::move(x), std::move(tris));
  parent_ = std::move(parent);
  split_ = std::move(split);
  fixed_.resize(static_cast<size_t>(surface_.x().cols()), 0);
  // Corners the seam was moved to go onto the geodesic where they may and stay well shaped.
  for (const auto& [corner, target] : onto) {
    const int v = corner;  // a plain variable: clang 14 (Debian 12) cannot capture a binding
    if (fixed_[static_cast<size_t>(v)] || surface_.on_boundary(v)) continue;
    const auto& xs = surface_.x();
    auto worst = [&](std::vector<Vec3>* normals) {
      double q = M_PI;
      for (int f : surface_.faces_at(v)) {
        const auto& t = surface_.triangles()[static_cast<size_t>(f)];
        q = std::min(q, smallest_angle(xs.col(t[0]), xs.col(t[1]), xs.col(t[2])));
        if (normals)
          normals->push_back((xs.col(t[1]) - xs.col(t[0])).cross(xs.col(t[2]) - xs.col(t[0])));
      }
      return q;
    };
    std::vector<Vec3> before, after;
    const double q0 = worst(&before);
    const Vec3 old = xs.col(v);
    surface_.move(v, target);
    bool ok = worst(&after) >= 0.5 * q0;
    for (size_t k = 0; k < before.size() && ok; ++k) ok = before[k].dot(after[k]) > 0;
    if (ok) {
      ++moved_;
    } else {
      surface_.move(v, old);
    }
  }
  for (const auto& [key, seam_index] : seam_edges_) {
    (void)seam_index;
    fixed_[static_cast<size_t>(key >> 32)] = fixed_[static_cast<size_t>(key & 0xffffffffu)] = 1;
  }
}

std::vector<int> SeamCutter::panels(int* count) const {
  const auto& s = surface_;
  const auto& tris = s.triangles();
  std::vector<int> panel(tris.size(), -1);
  int n = 0;
  std::vector<int> stack;
  // Numbered by their first triangle in the order of the input triangles (parents).
  std::vector<int> order(tris.size());
  for (size_t f = 0; f < order.size(); ++f) order[f] = static_cast<int>(f);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return parent_[static_cast<size_t>(a)] < parent_[static_cast<size_t>(b)];
  });
  for (int f0 : order) {
    if (panel[static_cast<size_t>(f0)] >= 0) continue;
    panel[static_cast<size_t>(f0)] = n;
    stack.push_back(f0);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      const auto& t = tris[static_cast<size_t>(f)];
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        if (seam_edges_.count(edge_key(a, b))) continue;
        const int g = s.across(f, a, b);
        if (g >= 0 && panel[static_cast<size_t>(g)] < 0)
          panel[static_cast<size_t>(g)] = n, stack.push_back(g);
      }
    }
    ++n;
  }
  for (const auto& [key, seam] : seam_edges_) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    std::vector<int> sides;
    for (int f : s.faces_at(a))
      if (has_vertex(tris[static_cast<size_t>(f)], b))
        sides.push_back(panel[static_cast<size_t>(f)]);
    if (sides.size() == 2 && sides[0] == sides[1])
      throw SeamError("the seam has the same panel on both sides", seam, a, b);
  }
  if (count) *count = n;
  return panel;
}

double SeamCutter::smallest_new_angle() const {
  double out = M_PI;
  const auto& x = surface_.x();
  for (size_t f = 0; f < split_.size(); ++f)
    if (split_[f]) {
      const auto& t = surface_.triangles()[f];
      out = std::min(out, smallest_angle(x.col(t[0]), x.col(t[1]), x.col(t[2])));
    }
  return out;
}

}  // namespace velum
