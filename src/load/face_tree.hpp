// A bounding-volume hierarchy (axis-aligned boxes) over the faces of a contact surface: built
// top-down once, refitted bottom-up to the faces' moved boxes at each search, and asked
// for the faces whose box holds a point (docs/contact.md, "Search"). Queries allocate nothing.
#pragma once

#include <Eigen/Geometry>

#include <span>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::contact {

using Box = Eigen::AlignedBox3d;

class FaceTree {
 public:
  /// The tree over `boxes` (one per face): median splits along the longest side of the
  /// centres' box, up to kLeaf faces a leaf.
  void build(std::span<const Box> boxes);
  /// The same tree over the faces' new boxes (same count, same order), built afresh when the
  /// refitted boxes' volume exceeds kRebuildLooseness times that of the last build. The tree
  /// reads `boxes` in its queries: they must outlive them.
  void refit(std::span<const Box> boxes);
  /// Builds made by refit() since construction.
  int rebuilds() const { return rebuilds_; }
  /// Sum of the nodes' box volumes over their sum at the last build: > 1 as the tree loosens.
  double looseness() const { return built_volume_ > 0 ? volume() / built_volume_ : 1.0; }
  bool empty() const { return nodes_.empty(); }

  /// Calls visit(face) for every face whose box holds p.
  template <class Visit>
  void query(const Vec3& p, Visit&& visit) const {
    if (nodes_.empty()) return;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[static_cast<size_t>(stack[--top])];
      if (!n.box.contains(p)) continue;
      if (n.count > 0) {
        for (int i = n.first; i < n.first + n.count; ++i) {
          const int f = faces_[static_cast<size_t>(i)];
          if (boxes_[static_cast<size_t>(f)].contains(p)) visit(f);
        }
        continue;
      }
      stack[top++] = n.first;      // left child
      stack[top++] = n.first + 1;  // right child
    }
  }

  /// The face nearest to p: distance(f) gives p's squared distance to face f; boxes farther
  /// than the best so far are skipped (branch and bound). `best`: in, an upper bound (infinity
  /// for none); out, the least squared distance. -1: no face within the bound.
  template <class Distance>
  int nearest(const Vec3& p, Distance&& distance, double& best) const {
    if (nodes_.empty()) return -1;
    int stack[kMaxDepth];
    int top = 0, found = -1;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[static_cast<size_t>(stack[--top])];
      if (n.box.squaredExteriorDistance(p) >= best) continue;
      if (n.count > 0) {
        for (int i = n.first; i < n.first + n.count; ++i) {
          const int f = faces_[static_cast<size_t>(i)];
          if (boxes_[static_cast<size_t>(f)].squaredExteriorDistance(p) >= best) continue;
          if (const double d = distance(f); d < best) best = d, found = f;
        }
        continue;
      }
      // The nearer child last: it is visited first.
      const Node& l = nodes_[static_cast<size_t>(n.first)];
      const Node& r = nodes_[static_cast<size_t>(n.first + 1)];
      const bool left_first = l.box.squaredExteriorDistance(p) <= r.box.squaredExteriorDistance(p);
      stack[top++] = left_first ? n.first + 1 : n.first;
      stack[top++] = left_first ? n.first : n.first + 1;
    }
    return found;
  }

 private:
  static constexpr int kLeaf = 4;
  static constexpr double kRebuildLooseness = 2.0;
  static constexpr int kMaxDepth = 128;
  struct Node {
    Box box;
    int first = 0;  ///< leaf: first index into faces_; inner: the left child (right = first + 1)
    int count = 0;  ///< faces of a leaf; 0: inner
  };
  int split(std::span<const Box> boxes, int node, int begin, int end, int depth);
  double volume() const;
  std::vector<Node> nodes_;
  std::vector<int> faces_;
  std::span<const Box> boxes_;  ///< the faces' boxes of the last build or refit (the caller's)
  double built_volume_ = 0;
  int rebuilds_ = 0;
};

}  // namespace velum::contact
