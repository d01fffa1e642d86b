// Geodesics on a triangulated surface (the seam lines of cutting patterns, docs/patterns.md):
// shortest paths on the polyhedral surface itself, not along its edges. Lengths in the model's.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "velum/analysis/flatten.hpp"

namespace velum {

/// A point on the surface: a vertex, a point on an edge (a, b) at (1 - t) x_a + t x_b, or a
/// point inside a face with barycentric weights.
struct SurfacePoint {
  enum class Kind { Vertex, Edge, Face } kind = Kind::Vertex;
  int vertex = -1;              ///< Vertex
  int a = -1, b = -1;           ///< Edge
  double t = 0;                 ///< Edge
  int face = -1;                ///< Face
  Vec3 weights = Vec3::Zero();  ///< Face: barycentric weights of the face's corners
};

/// Whether triangle t has corner v.
inline bool has_vertex(const std::array<int, 3>& t, int v) {
  return t[0] == v || t[1] == v || t[2] == v;
}

/// Triangles on nodes with their edge adjacency; the nodes may be shared with other surfaces
/// (indices into x). Every edge belongs to one or two triangles (checked: manifold).
class TriangleSurface {
 public:
  TriangleSurface(NodePositions x, std::vector<std::array<int, 3>> triangles);

  const NodePositions& x() const { return x_; }
  const std::vector<std::array<int, 3>>& triangles() const { return tris_; }
  /// The triangle across edge (a, b) of triangle f, or -1 on the boundary.
  int across(int f, int a, int b) const;
  /// Triangles at vertex v (unordered).
  const std::vector<int>& faces_at(int v) const { return at_[static_cast<size_t>(v)]; }
  /// The triangles point p lies in (one, those of an edge, or those at a vertex).
  std::vector<int> faces_of(const SurfacePoint& p) const;
  bool on_boundary(int v) const { return boundary_[static_cast<size_t>(v)]; }
  /// Sum of the triangles' angles at v (2 pi on a flat interior vertex).
  double angle_sum(int v) const { return angle_sum_[static_cast<size_t>(v)]; }
  Vec3 position(const SurfacePoint& p) const;
  /// Moves node v to p (its triangles' angles at their corners follow).
  void move(int v, const Vec3& p);
  /// The mean edge length.
  double mean_edge() const { return mean_edge_; }
  /// Why the triangles are not a manifold surface (an edge of three triangles), or "".
  const std::string& problem() const { return problem_; }

 private:
  NodePositions x_;
  std::vector<std::array<int, 3>> tris_;
  std::vector<std::array<int, 3>> nbr_;  ///< per triangle: across edge (k, k+1)
  std::vector<std::vector<int>> at_;
  std::vector<char> boundary_;
  std::vector<double> angle_sum_;
  double mean_edge_ = 0;
  std::string problem_;
};

/// The point of the surface closest to p and its distance; a point within `snap` of a vertex is
/// that vertex, within `snap` of an edge a point on it.
SurfacePoint locate(const TriangleSurface& s, const Vec3& p, double snap, double* distance);

struct SurfacePath {
  std::vector<SurfacePoint> points;  ///< from, the edges crossed and vertices passed, to
  double length = 0;
  int iterations = 0;  ///< straightening passes
  int flips = 0;       ///< times the path was moved to the other side of a vertex
};

/// The geodesic from `from` to `to`: a shortest path on the edges (Dijkstra) as the start, the
/// strip of triangles along it unfolded into the plane and the path pulled straight in it (the
/// funnel algorithm), and where the straight path bends at a vertex with less than pi on its
/// other side, the strip moved round that side, until no such vertex is left. The result is
/// straight in every triangle and turns only at saddle vertices (pi or more on both sides): a
/// locally shortest path, exact on the polyhedral surface to round-off.
SurfacePath geodesic(const TriangleSurface& s, const SurfacePoint& from, const SurfacePoint& to);

}  // namespace velum
