// The rigid mesh's distance (rigid_mesh.hpp): the nearest triangle by branch and bound over the
// box tree, the nearest point on it by its Voronoi regions, the side by pseudonormals (so a
// point inside a closed surface is inside whichever edge or corner is nearest).
#include "rigid_mesh.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace velum {
namespace {

// The region of a triangle (a, b, c) nearest to p: 0 interior, 1..3 the edges ab, bc, ca,
// 4..6 the corners a, b, c; and the nearest point.
struct Nearest {
  Vec3 point;
  int region = 0;
};

Nearest nearest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Ericson, Real-Time Collision Detection, 5.1.5.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, 4};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, 5};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {Vec3(a + d1 / (d1 - d3) * ab), 1};
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, 6};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {Vec3(a + d2 / (d2 - d6) * ac), 3};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return {Vec3(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)), 2};
  const double denom = 1 / (va + vb + vc);
  return {Vec3(a + ab * (vb * denom) + ac * (vc * denom)), 0};
}

}  // namespace

RigidMesh::RigidMesh(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  if (triangles_.empty()) throw std::invalid_argument("the rigid mesh has no triangles or quads");
  const size_t T = triangles_.size();
  normal_.resize(T);
  edge_side_.resize(T);
  vertex_side_.assign(vertices_.size(), Vec3::Zero());
  boxes_.resize(T);
  std::map<std::pair<int, int>, Vec3> edge_sum;  // by sorted vertex pair: the faces' normals
  double largest = 0;
  for (const auto& t : triangles_)
    for (int k = 0; k < 3; ++k)
      largest = std::max(largest, (vertices_[static_cast<size_t>(t[static_cast<size_t>(k)])] -
                                   vertices_[static_cast<size_t>(t[(k + 1) % 3])])
                                      .norm());
  for (size_t f = 0; f < T; ++f) {
    const auto& t = triangles_[f];
    const Vec3 m =
        (vertices_[static_cast<size_t>(t[1])] - vertices_[static_cast<size_t>(t[0])])
            .cross(vertices_[static_cast<size_t>(t[2])] - vertices_[static_cast<size_t>(t[0])]);
    // Degenerate: an area below 1e-12 of the largest edge's square (collinear corners).
    if (!(m.norm() > 1e-12 * largest * largest))
      throw std::invalid_argument(
          fmt::format("the rigid mesh's triangle {} (counted from 1, quads split in two) is "
                      "degenerate: its corners are collinear",
                      f + 1));
    normal_[f] = m.normalized();
    contact::Box box(vertices_[static_cast<size_t>(t[0])]);
    for (int k = 0; k < 3; ++k) {
      const int a = t[static_cast<size_t>(k)], b = t[static_cast<size_t>((k + 1) % 3)],
                c = t[static_cast<size_t>((k + 2) % 3)];
      box.extend(vertices_[static_cast<size_t>(a)]);
      // Eigen's vectors start uninitialised: the first face sets the sum.
      const auto [it, first] = edge_sum.try_emplace(std::minmax(a, b), normal_[f]);
      if (!first) it->second += normal_[f];
      // The corner's angle weights its normal.
      const Vec3 u = (vertices_[static_cast<size_t>(b)] - vertices_[static_cast<size_t>(a)]);
      const Vec3 v = (vertices_[static_cast<size_t>(c)] - vertices_[static_cast<size_t>(a)]);
      vertex_side_[static_cast<size_t>(a)] += std::atan2(u.cross(v).norm(), u.dot(v)) * normal_[f];
    }
    boxes_[f] = box;
  }
  for (size_t f = 0; f < T; ++f)
    for (int k = 0; k < 3; ++k)
      edge_side_[f][static_cast<size_t>(k)] = edge_sum[std::minmax(
          triangles_[f][static_cast<size_t>(k)], triangles_[f][static_cast<size_t>((k + 1) % 3)])];
  tree_.build(boxes_);
  // The sharp convex edges: two faces, the second's far corner behind the first's plane.
  std::map<std::pair<int, int>, std::vector<std::pair<size_t, int>>> faces;  // (face, far corner)
  for (size_t f = 0; f < T; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto& t = triangles_[f];
      faces[std::minmax(t[static_cast<size_t>(k)], t[static_cast<size_t>((k + 1) % 3)])].push_back(
          {f, t[static_cast<size_t>((k + 2) % 3)]});
    }
  closed_ = true;
  for (const auto& [e, fs] : faces) {
    closed_ = closed_ && fs.size() == 2;
    if (fs.size() != 2) continue;
    const Vec3& n0 = normal_[fs[0].first];
    const Vec3& n1 = normal_[fs[1].first];
    const Vec3 behind =
        vertices_[static_cast<size_t>(fs[1].second)] - vertices_[static_cast<size_t>(e.first)];
    if (n0.dot(n1) < 0.99 && behind.dot(n0) < 0)
      sharp_.push_back({e.first, e.second, (n0 + n1).normalized()});
  }
}

double RigidMesh::gap(const Vec3& x, Vec3& n, Mat3& H) const {
  Nearest best;
  int face = -1;
  double d2 = std::numeric_limits<double>::infinity();
  face = tree_.nearest(
      x,
      [&](int f) {
        const auto& t = triangles_[static_cast<size_t>(f)];
        const Nearest q = nearest_on_triangle(x, vertices_[static_cast<size_t>(t[0])],
                                              vertices_[static_cast<size_t>(t[1])],
                                              vertices_[static_cast<size_t>(t[2])]);
        const double d = (x - q.point).squaredNorm();
        if (d < d2) best = q;  // d2 is the tree's best so far
        return d;
      },
      d2);
  const auto fi = static_cast<size_t>(face);
  H.setZero();
  if (best.region == 0) {
    n = normal_[fi];
    return n.dot(x - best.point);
  }
  const Vec3 side =
      best.region <= 3
          ? edge_side_[fi][static_cast<size_t>(best.region - 1)]
          : vertex_side_[static_cast<size_t>(triangles_[fi][static_cast<size_t>(best.region - 4)])];
  const Vec3 r = x - best.point;
  const double d = r.norm();
  if (d == 0) {
    n = side.normalized();
    return 0;
  }
  const double s = r.dot(side) >= 0 ? 1.0 : -1.0;
  n = s * r / d;
  Mat3 P = Mat3::Identity() - n * n.transpose();
  if (best.region <= 3) {
    // Nearest to an edge: the distance from its line.
    const auto& t = triangles_[fi];
    const int k = best.region - 1;
    const Vec3 e = (vertices_[static_cast<size_t>(t[static_cast<size_t>((k + 1) % 3)])] -
                    vertices_[static_cast<size_t>(t[static_cast<size_t>(k)])])
                       .normalized();
    P -= e * e.transpose();
  }
  H = (s / d) * P;
  return s * d;
}

}  // namespace velum
