// Geodesics on a triangulated surface: a shortest edge path straightened by unfolding
// (include/velum/analysis/geodesic.hpp).
#include "velum/analysis/geodesic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>

namespace velum {
namespace {

using Vec2d = Eigen::Vector2d;

double cross2(const Vec2d& a, const Vec2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The unsigned angle between two plane vectors, in [0, pi].
double angle2(const Vec2d& a, const Vec2d& b) {
  return std::atan2(std::abs(cross2(a, b)), a.dot(b));
}

// The closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5),
// as barycentric weights.
Vec3 closest_weights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

}  // namespace

TriangleSurface::TriangleSurface(NodePositions x, std::vector<std::array<int, 3>> triangles)
    : x_(std::move(x)), tris_(std::move(triangles)) {
  const auto n = static_cast<size_t>(x_.cols());
  at_.assign(n, {});
  boundary_.assign(n, 0);
  angle_sum_.assign(n, 0.0);
  nbr_.assign(tris_.size(), {-1, -1, -1});
  std::unordered_map<uint64_t, std::pair<int, int>> edges;  // edge -> (triangle, its edge k)
  edges.reserve(tris_.size() * 2);
  double total = 0;
  long count = 0;
  for (size_t f = 0; f < tris_.size(); ++f) {
    const auto& t = tris_[f];
    for (int k = 0; k < 3; ++k) {
      const int a = t[static_cast<size_t>(k)], b = t[static_cast<size_t>((k + 1) % 3)],
                c = t[static_cast<size_t>((k + 2) % 3)];
      at_[static_cast<size_t>(a)].push_back(static_cast<int>(f));
      const Vec3 u = x_.col(b) - x_.col(a), v = x_.col(c) - x_.col(a);
      angle_sum_[static_cast<size_t>(a)] += std::atan2(u.cross(v).norm(), u.dot(v));
      const uint64_t key =
          (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
      auto [it, added] = edges.emplace(key, std::make_pair(static_cast<int>(f), k));
      if (added) {
        total += u.norm(), ++count;
      } else if (it->second.first < 0) {
        if (problem_.empty())
          problem_ = fmt::format(
              "the edge between nodes {} and {} belongs to three or more elements", a, b);
      } else {
        nbr_[f][static_cast<size_t>(k)] = it->second.first;
        nbr_[static_cast<size_t>(it->second.first)][static_cast<size_t>(it->second.second)] =
            static_cast<int>(f);
        it->second.first = -1;  // seen twice
      }
    }
  }
  for (const auto& [key, fk] : edges)
    if (fk.first >= 0) {
      boundary_[static_cast<size_t>(key >> 32)] = 1;
      boundary_[static_cast<size_t>(key & 0xffffffffu)] = 1;
    }
  mean_edge_ = count ? total / static_cast<double>(count) : 0;
}

int TriangleSurface::across(int f, int a, int b) const {
  const auto& t = tris_[static_cast<size_t>(f)];
  for (int k = 0; k < 3; ++k) {
    const int p = t[static_cast<size_t>(k)], q = t[static_cast<size_t>((k + 1) % 3)];
    if ((p == a && q == b) || (p == b && q == a))
      return nbr_[static_cast<size_t>(f)][static_cast<size_t>(k)];
  }
  return -1;
}

void TriangleSurface::move(int v, const Vec3& p) {
  x_.col(v) = p;
  for (int f : at_[static_cast<size_t>(v)])
    for (int c : tris_[static_cast<size_t>(f)]) angle_sum_[static_cast<size_t>(c)] = 0;
  for (int f : at_[static_cast<size_t>(v)])
    for (int c : tris_[static_cast<size_t>(f)])
      if (angle_sum_[static_cast<size_t>(c)] == 0)
        for (int g : at_[static_cast<size_t>(c)]) {
          const auto& t = tris_[static_cast<size_t>(g)];
          const int k = t[0] == c ? 0 : (t[1] == c ? 1 : 2);
          const Vec3 u = x_.col(t[(k + 1) % 3]) - x_.col(c), w = x_.col(t[(k + 2) % 3]) - x_.col(c);
          angle_sum_[static_cast<size_t>(c)] += std::atan2(u.cross(w).norm(), u.dot(w));
        }
}

Vec3 TriangleSurface::position(const SurfacePoint& p) const {
  switch (p.kind) {
    case SurfacePoint::Kind::Vertex:
      return x_.col(p.vertex);
    case SurfacePoint::Kind::Edge:
      return (1 - p.t) * x_.col(p.a) + p.t * x_.col(p.b);
    case SurfacePoint::Kind::Face: {
      const auto& t = tris_[static_cast<size_t>(p.face)];
      return p.weights[0] * x_.col(t[0]) + p.weights[1] * x_.col(t[1]) +
             p.weights[2] * x_.col(t[2]);
    }
  }
  return Vec3::Zero();
}

std::vector<int> TriangleSurface::faces_of(const SurfacePoint& p) const {
  switch (p.kind) {
    case SurfacePoint::Kind::Vertex:
      return faces_at(p.vertex);
    case SurfacePoint::Kind::Edge: {
      std::vector<int> out;
      for (int f : faces_at(p.a))
        if (has_vertex(tris_[static_cast<size_t>(f)], p.b)) out.push_back(f);
      return out;
    }
    case SurfacePoint::Kind::Face:
      return {p.face};
  }
  return {};
}

SurfacePoint locate(const TriangleSurface& s, const Vec3& p, double snap, double* distance) {
  const auto& x = s.x();
  double best = std::numeric_limits<double>::infinity();
  int face = -1;
  Vec3 weights = Vec3::Zero();
  for (size_t f = 0; f < s.triangles().size(); ++f) {
    const auto& t = s.triangles()[f];
    const Vec3 w = closest_weights(p, x.col(t[0]), x.col(t[1]), x.col(t[2]));
    const double d = (w[0] * x.col(t[0]) + w[1] * x.col(t[1]) + w[2] * x.col(t[2]) - p).norm();
    if (d < best) best = d, face = static_cast<int>(f), weights = w;
  }
  if (distance) *distance = best;
  SurfacePoint out;
  if (face < 0) return out;
  const auto& t = s.triangles()[static_cast<size_t>(face)];
  const Vec3 q = weights[0] * x.col(t[0]) + weights[1] * x.col(t[1]) + weights[2] * x.col(t[2]);
  // Nearest corner, then nearest edge, within snap.
  int corner = 0;
  for (int k = 1; k < 3; ++k)
    if ((x.col(t[k]) - q).norm() < (x.col(t[corner]) - q).norm()) corner = k;
  if ((x.col(t[corner]) - q).norm() <= snap) {
    out.kind = SurfacePoint::Kind::Vertex;
    out.vertex = t[corner];
    return out;
  }
  double edge_d = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const int a = t[k], b = t[(k + 1) % 3];
    const Vec3 e = x.col(b) - x.col(a);
    const double u = std::clamp((q - x.col(a)).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double d = (x.col(a) + u * e - q).norm();
    if (d < edge_d) edge_d = d, out.a = a, out.b = b, out.t = u;
  }
  if (edge_d <= snap) {
    out.kind = SurfacePoint::Kind::Edge;
    return out;
  }
  out.kind = SurfacePoint::Kind::Face;
  out.face = face;
  out.weights = weights;
  return out;
}

namespace {

// Dijkstra on the edges from `from` to `to`: the vertices passed, in order (an endpoint that is
// a vertex included).
std::vector<int> edge_path(const TriangleSurface& s, const SurfacePoint& from,
                           const SurfacePoint& to) {
  const auto& x = s.x();
  const auto n = static_cast<size_t>(x.cols());
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> prev(n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  const Vec3 p0 = s.position(from), p1 = s.position(to);
  auto seed = [&](int v, double d) {
    if (d < dist[static_cast<size_t>(v)]) dist[static_cast<size_t>(v)] = d, queue.push({d, v});
  };
  for (int f : s.faces_of(from))
    for (int v : s.triangles()[static_cast<size_t>(f)])
      seed(v, from.kind == SurfacePoint::Kind::Vertex ? (v == from.vertex ? 0.0 : HUGE_VAL)
                                                      : (x.col(v) - p0).norm());
  std::unordered_map<int, double> target;  // vertex -> remaining distance to `to`
  for (int f : s.faces_of(to))
    for (int v : s.triangles()[static_cast<size_t>(f)])
      if (to.kind != SurfacePoint::Kind::Vertex || v == to.vertex)
        target[v] = (x.col(v) - p1).norm();
  double best = HUGE_VAL;
  int best_v = -1;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(v)]) continue;
    if (d >= best) break;
    if (auto it = target.find(v); it != target.end() && d + it->second < best)
      best = d + it->second, best_v = v;
    for (int f : s.faces_at(v))
      for (int w : s.triangles()[static_cast<size_t>(f)])
        if (w != v) {
          const double dw = d + (x.col(w) - x.col(v)).norm();
          if (dw < dist[static_cast<size_t>(w)])
            dist[static_cast<size_t>(w)] = dw, prev[static_cast<size_t>(w)] = v,
            queue.push({dw, w});
        }
  }
  std::vector<int> path;
  for (int v = best_v; v >= 0; v = prev[static_cast<size_t>(v)]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

// The triangles round vertex w from f (excluded) to the first one `goal` accepts, in the
// direction of smaller angle at w; empty when neither direction reaches it.
template <class Goal>
std::vector<int> fan(const TriangleSurface& s, int f, int w, const Goal& goal, bool larger = false,
                     int avoid_first = -1) {
  std::vector<int> best;
  double best_angle = larger ? -1.0 : HUGE_VAL;
  const auto& t0 = s.triangles()[static_cast<size_t>(f)];
  for (int v : t0) {
    if (v == w || v == avoid_first) continue;
    std::vector<int> run;
    double angle = 0;
    int cur = f, edge_v = v;
    bool reached = false;
    for (size_t step = 0; step <= s.faces_at(w).size(); ++step) {
      const int next = s.across(cur, w, edge_v);
      if (next < 0 || next == f) break;
      run.push_back(next);
      const auto& t = s.triangles()[static_cast<size_t>(next)];
      int other = -1;
      for (int u : t)
        if (u != w && u != edge_v) other = u;
      const Vec3 a = s.x().col(edge_v) - s.x().col(w), b = s.x().col(other) - s.x().col(w);
      angle += std::atan2(a.cross(b).norm(), a.dot(b));
      if (goal(next)) {
        reached = true;
        break;
      }
      cur = next, edge_v = other;
    }
    if (reached && (larger ? angle > best_angle : angle < best_angle))
      best = run, best_angle = angle;
  }
  return best;
}

struct Unfolded {
  std::vector<Vec2d> p;                        // placements
  std::vector<int> vert;                       // the vertex of each placement (-1: the end points)
  std::vector<std::array<int, 3>> face_place;  // per corridor face: placements of its corners
  std::vector<std::array<int, 2>> portal;      // [left, right] placements, 0 start .. n end
};

Unfolded unfold(const TriangleSurface& s, const std::vector<int>& faces, const SurfacePoint& from,
                const SurfacePoint& to) {
  Unfolded u;
  const auto& x = s.x();
  auto tri = [&](int f) { return s.triangles()[static_cast<size_t>(f)]; };
  {
    const auto t = tri(faces[0]);
    const Vec3 a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]);
    const double lab = (b - a).norm();
    const double cx = (c - a).dot(b - a) / lab, cy = (c - a).cross(b - a).norm() / lab;
    u.p = {Vec2d(0, 0), Vec2d(lab, 0), Vec2d(cx, cy)};
    u.vert = {t[0], t[1], t[2]};
    u.face_place.push_back({0, 1, 2});
  }
  auto place_point = [&](size_t k, const SurfacePoint& sp) {
    const auto t = tri(faces[k]);
    const auto& fp = u.face_place[k];
    if (sp.kind == SurfacePoint::Kind::Vertex) {
      for (int c = 0; c < 3; ++c)
        if (t[c] == sp.vertex) return fp[c];
    }
    // Barycentric weights of the point in this triangle (from its 3-D position).
    const Vec3 q = s.position(sp), a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]);
    const Vec3 n = (b - a).cross(c - a);
    const double A = n.squaredNorm();
    const double wb = (q - a).cross(c - a).dot(n) / A, wc = (b - a).cross(q - a).dot(n) / A;
    u.p.push_back((1 - wb - wc) * u.p[fp[0]] + wb * u.p[fp[1]] + wc * u.p[fp[2]]);
    u.vert.push_back(-1);
    return static_cast<int>(u.p.size() - 1);
  };
  const int start = place_point(0, from);
  u.portal.push_back({start, start});
  for (size_t k = 1; k < faces.size(); ++k) {
    const auto prev = tri(faces[k - 1]), t = tri(faces[k]);
    const auto& pp = u.face_place[k - 1];
    std::array<int, 3> fp{-1, -1, -1};
    int behind = -1, third = -1;
    for (int c = 0; c < 3; ++c) {
      if (has_vertex(t, prev[c])) {
        for (int d = 0; d < 3; ++d)
          if (t[d] == prev[c]) fp[d] = pp[c];
      } else {
        behind = pp[c];
      }
    }
    for (int d = 0; d < 3; ++d)
      if (fp[d] < 0) third = d;
    const int ia = fp[(third + 1) % 3], ib = fp[(third + 2) % 3];
    const Vec2d A = u.p[ia], B = u.p[ib], C = u.p[behind];
    // The third corner, across the shared edge from the one behind it.
    const Vec3 a3 = x.col(t[(third + 1) % 3]), b3 = x.col(t[(third + 2) % 3]), c3 = x.col(t[third]);
    const double lab = (b3 - a3).norm();
    const double cx = (c3 - a3).dot(b3 - a3) / lab, cy = (c3 - a3).cross(b3 - a3).norm() / lab;
    const Vec2d e = (B - A).normalized();
    Vec2d nrm(-e.y(), e.x());
    if (nrm.dot(C - A) > 0) nrm = -nrm;
    u.p.push_back(A + cx * e + cy * nrm);
    u.vert.push_back(t[third]);
    fp[third] = static_cast<int>(u.p.size() - 1);
    u.face_place.push_back(fp);
    // Left and right seen from the face behind.
    if (cross2(A - C, B - C) > 0)
      u.portal.push_back({ib, ia});
    else
      u.portal.push_back({ia, ib});
  }
  const int end = place_point(faces.size() - 1, to);
  u.portal.push_back({end, end});
  return u;
}

struct Apex {
  int place, portal;
};

// The shortest path through the portals (the "simple stupid funnel" of Mononen): the start,
// the portal corners it bends at, the end. A side of the funnel still at the apex (portals
// that fan round it) does not bound the other side. Whether a left and a right corner have
// crossed is always area(apex, left, right) (the same products in the same order: with fused
// multiply-adds area(a, b, c) need not be exactly -area(a, c, b), and collinear corners on both
// sides would then each count as crossed).
std::vector<Apex> funnel(const Unfolded& u) {
  const auto& P = u.p;
  const auto& portals = u.portal;
  auto area = [&](int a, int b, int c) { return cross2(P[b] - P[a], P[c] - P[a]); };
  std::vector<Apex> out{{portals[0][0], 0}};
  int apex = portals[0][0], left = portals[0][0], right = portals[0][1];
  int apex_i = 0, left_i = 0, right_i = 0;
  const int n = static_cast<int>(portals.size());
  for (int i = 1; i < n; ++i) {
    const int l = portals[i][0], r = portals[i][1];
    if (area(apex, right, r) >= 0) {  // the right side narrows (turns counter-clockwise)
      if (apex == right || apex == left || area(apex, left, r) <= 0) {
        right = r, right_i = i;
      } else {
        out.push_back({left, left_i});
        apex = left, apex_i = left_i;
        right = left = apex, right_i = left_i = apex_i;
        i = apex_i;
        continue;
      }
    }
    if (area(apex, left, l) <= 0) {
      if (apex == left || apex == right || area(apex, l, right) <= 0) {
        left = l, left_i = i;
      } else {
        out.push_back({right, right_i});
        apex = right, apex_i = right_i;
        right = left = apex, right_i = left_i = apex_i;
        i = apex_i;
        continue;
      }
    }
  }
  out.push_back({portals[static_cast<size_t>(n - 1)][0], n - 1});
  // A corner reached as both sides close on it (the end) comes once.
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Apex& a, const Apex& b) { return a.place == b.place; }),
            out.end());
  out.back().portal = n - 1;
  return out;
}

bool same_point(const SurfacePoint& a, const SurfacePoint& b) {
  return a.kind == SurfacePoint::Kind::Vertex && b.kind == SurfacePoint::Kind::Vertex &&
         a.vertex == b.vertex;
}

}  // namespace

SurfacePath geodesic(const TriangleSurface& s, const SurfacePoint& from, const SurfacePoint& to) {
  SurfacePath out;
  const Vec3 p0 = s.position(from), p1 = s.position(to);
  const auto f0 = s.faces_of(from), f1 = s.faces_of(to);
  for (int f : f0)
    if (std::find(f1.begin(), f1.end(), f) != f1.end()) {
      out.points = {from, to};
      out.length = (p1 - p0).norm();
      return out;
    }
  const std::vector<int> W = edge_path(s, from, to);
  if (W.empty())
    throw std::invalid_argument("the two points are on separate pieces of the surface");
  auto tri = [&](int f) { return s.triangles()[static_cast<size_t>(f)]; };
  // The strip of triangles along the edge path: fans round each vertex passed.
  std::vector<int> faces;
  const bool from_vertex = from.kind == SurfacePoint::Kind::Vertex;
  const bool to_vertex = to.kind == SurfacePoint::Kind::Vertex;
  size_t first = from_vertex ? 1 : 0;
  const size_t last = to_vertex ? W.size() - 2 : W.size() - 1;
  {
    int start = -1;
    const int w = W[first];
    for (int f : from_vertex ? s.faces_at(W[0]) : f0)
      if (has_vertex(tri(f), w) && (!from_vertex || start < 0)) start = f;
    faces.push_back(start);
  }
  for (size_t i = first; i <= last; ++i) {
    const int w = W[i];
    auto goal = [&](int f) {
      if (i + 1 < W.size()) return has_vertex(tri(f), w) && has_vertex(tri(f), W[i + 1]);
      return std::find(f1.begin(), f1.end(), f) != f1.end();
    };
    if (goal(faces.back())) continue;
    const auto run = fan(s, faces.back(), w, goal);
    if (run.empty()) throw std::invalid_argument("no strip of triangles along the edge path");
    faces.insert(faces.end(), run.begin(), run.end());
  }
  constexpr int kMaxPasses = 100000;
  std::vector<Apex> apexes;
  Unfolded u;
  for (out.iterations = 1; out.iterations <= kMaxPasses; ++out.iterations) {
    // Tidy the strip: no triangle entered and left again at once; an end at a vertex starts in
    // the last triangle at it.
    for (bool again = true; again;) {
      again = false;
      for (size_t k = 0; k + 2 < faces.size(); ++k)
        if (faces[k] == faces[k + 2]) {
          faces.erase(faces.begin() + static_cast<long>(k) + 1,
                      faces.begin() + static_cast<long>(k) + 3);
          again = true;
          break;
        }
    }
    while (from_vertex && faces.size() > 1 && has_vertex(tri(faces[1]), from.vertex))
      faces.erase(faces.begin());
    while (to_vertex && faces.size() > 1 && has_vertex(tri(faces[faces.size() - 2]), to.vertex))
      faces.pop_back();
    u = unfold(s, faces, from, to);
    apexes = funnel(u);
    // Vertices the path bends at with less than pi on the strip's other side: go round there.
    struct Flip {
      int a, b, w;
    };
    std::vector<Flip> flips;
    for (size_t k = 1; k + 1 < apexes.size(); ++k) {
      const int w = u.vert[static_cast<size_t>(apexes[k].place)];
      if (w < 0 || s.on_boundary(w)) continue;
      const int pi = apexes[k].portal;
      int a = pi - 1, b = pi;
      while (a > 0 && has_vertex(tri(faces[static_cast<size_t>(a - 1)]), w)) --a;
      while (b + 1 < static_cast<int>(faces.size()) &&
             has_vertex(tri(faces[static_cast<size_t>(b + 1)]), w))
        ++b;
      const Vec2d P = u.p[static_cast<size_t>(apexes[k].place)];
      const Vec2d A = u.p[static_cast<size_t>(apexes[k - 1].place)] - P;
      const Vec2d B = u.p[static_cast<size_t>(apexes[k + 1].place)] - P;
      auto other = [&](int j) {  // the corner of portal j that is not w
        const auto& q = u.portal[static_cast<size_t>(j)];
        return u.p[static_cast<size_t>(u.vert[static_cast<size_t>(q[0])] == w ? q[1] : q[0])] - P;
      };
      double side = angle2(A, other(a + 1));
      for (int j = a + 1; j < b; ++j) side += angle2(other(j), other(j + 1));
      side += angle2(other(b), B);
      if (s.angle_sum(w) - side < M_PI - 1e-9) flips.push_back({a, b, w});
    }
    if (flips.empty()) break;
    int limit = static_cast<int>(faces.size());
    for (auto it = flips.rbegin(); it != flips.rend(); ++it) {
      if (it->b >= limit) continue;
      const int fb = faces[static_cast<size_t>(it->b)];
      // Round w the other way: from faces[a] not through faces[a + 1].
      int through = -1;
      for (int v : tri(faces[static_cast<size_t>(it->a)]))
        if (v != it->w && has_vertex(tri(faces[static_cast<size_t>(it->a + 1)]), v)) through = v;
      const auto run = fan(
          s, faces[static_cast<size_t>(it->a)], it->w, [&](int f) { return f == fb; }, false,
          through);
      if (run.empty()) continue;
      faces.erase(faces.begin() + it->a + 1, faces.begin() + it->b + 1);
      faces.insert(faces.begin() + it->a + 1, run.begin(), run.end());
      limit = it->a;
      ++out.flips;
    }
  }
  // The path's points: the edges crossed between the bends, the vertices it passes.
  out.points.push_back(from);
  auto push = [&](const SurfacePoint& p) {
    if (!same_point(out.points.back(), p)) out.points.push_back(p);
  };
  for (size_t k = 0; k + 1 < apexes.size(); ++k) {
    const Vec2d A = u.p[static_cast<size_t>(apexes[k].place)],
                B = u.p[static_cast<size_t>(apexes[k + 1].place)];
    out.length += (B - A).norm();
    for (int j = apexes[k].portal + 1; j < apexes[k + 1].portal; ++j) {
      const auto& q = u.portal[static_cast<size_t>(j)];
      if (q[0] == apexes[k].place || q[1] == apexes[k].place || q[0] == apexes[k + 1].place ||
          q[1] == apexes[k + 1].place)
        continue;
      const Vec2d L = u.p[static_cast<size_t>(q[0])], R = u.p[static_cast<size_t>(q[1])];
      const double den = cross2(R - L, B - A);
      double t = den != 0 ? cross2(A - L, B - A) / den : 0.5;
      t = std::clamp(t, 0.0, 1.0);
      SurfacePoint p;
      const int vl = u.vert[static_cast<size_t>(q[0])], vr = u.vert[static_cast<size_t>(q[1])];
      if (t < 1e-12 || t > 1 - 1e-12) {
        p.vertex = t < 0.5 ? vl : vr;
      } else {
        p.kind = SurfacePoint::Kind::Edge, p.a = vl, p.b = vr, p.t = t;
      }
      push(p);
    }
    if (k + 2 < apexes.size()) {
      SurfacePoint p;
      p.vertex = u.vert[static_cast<size_t>(apexes[k + 1].place)];
      push(p);
    }
  }
  if (!same_point(out.points.back(), to)) out.points.push_back(to);
  return out;
}

}  // namespace velum
