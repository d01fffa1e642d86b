// Seams cut into a triangulated surface and the panels they make (docs/patterns.md, "Seams"):
// a seam that runs along edges marks them; one that crosses triangles splits them (new nodes
// on the edges it crosses), or goes through a corner it passes close to.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/analysis/geodesic.hpp"

namespace velum {

/// A seam that cannot be cut or does not part panels: the seam and the nodes it concerns.
struct SeamError : std::invalid_argument {
  SeamError(const std::string& what, int seam, int a, int b = -1)
      : std::invalid_argument(what), seam(seam), a(a), b(b) {}
  int seam, a, b;
};

class SeamCutter {
 public:
  /// `snap`: a crossing within this fraction of the edge's length from a corner goes through the
  /// corner instead (no sliver triangles), and the corner moves onto the geodesic where it may
  /// (not on the boundary, on an earlier seam or a node `fix`ed) and its triangles keep at least
  /// half their smallest angle; else the seam moves by at most that much.
  SeamCutter(NodePositions x, std::vector<std::array<int, 3>> triangles, double snap = 0.2);

  /// A new node made on the edge (a, b) at (1 - t) x_a + t x_b: its index is the count of nodes
  /// before it.
  struct NewNode {
    int a, b;
    double t;
  };

  const TriangleSurface& surface() const { return surface_; }
  /// Node n stays where it is (a support, a cable's node, a node set's).
  void fix(int n) { fixed_[static_cast<size_t>(n)] = 1; }
  /// Nodes moved onto a seam.
  int moved() const { return moved_; }
  /// The geodesic from `from` to `to` on the surface as cut so far, cut in as seam `seam`.
  /// Throws std::invalid_argument (a point inside a triangle: a seam ends on the boundary, on
  /// another seam or at a node).
  SurfacePath add_geodesic(const SurfacePoint& from, const SurfacePoint& to, int seam);
  /// Nodes joined by edges, in order, cut in as seam `seam`; throws std::invalid_argument
  /// naming the first two nodes that no edge joins.
  void add_node_path(const std::vector<int>& nodes, int seam);

  /// The panels: per triangle its panel (0-based, numbered by the first triangle of each in
  /// the triangles' order, the originals first). Throws std::invalid_argument when a seam does
  /// not part two panels (it ends inside a panel): the message names the seam and a node.
  std::vector<int> panels(int* count) const;

  const std::vector<std::array<int, 3>>& triangles() const { return surface_.triangles(); }
  /// Per triangle: the input triangle it is (a part of).
  const std::vector<int>& parent() const { return parent_; }
  /// Per triangle: made by a split.
  const std::vector<char>& split() const { return split_; }
  const std::vector<NewNode>& new_nodes() const { return new_; }
  int original_nodes() const { return original_nodes_; }
  /// The smallest angle (radians) of the triangles the seams made, or pi without any.
  double smallest_new_angle() const;

 private:
  void cut(const std::vector<SurfacePoint>& points, int seam);
  void mark(int a, int b, int seam);

  TriangleSurface surface_;
  std::vector<int> parent_;
  std::vector<char> split_;
  std::vector<NewNode> new_;
  std::map<uint64_t, int> seam_edges_;  ///< edge (min, max) -> seam
  int original_nodes_ = 0;
  std::vector<char> fixed_;  ///< per node: may not move (given, or on a seam)
  int moved_ = 0;
  double snap_;
};

/// The smallest angle of triangle (a, b, c) in radians.
double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace velum
