// A rigid surface of triangles (a Gmsh surface's triangles and quads, the quads split): the
// signed distance of a point from it, its normal and curvature, found through a box tree over
// the triangles (docs/contact.md, "Rigid meshes").
#pragma once

#include <array>
#include <vector>

#include "face_tree.hpp"
#include "velum/load/contact_load.hpp"

namespace velum {

class RigidMesh {
 public:
  /// Throws std::invalid_argument on a degenerate triangle or an empty mesh.
  RigidMesh(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles);

  /// Signed distance of x from the surface (positive on the side the triangles' normals point
  /// to, out of the solid), its gradient n (unit) and Hessian H: in a triangle's interior n is
  /// its normal and H = 0; nearest to an edge or a corner, n points from that point to x and
  /// H is the curvature of the distance there. The side is the angle-weighted pseudonormal's.
  double gap(const Vec3& x, Vec3& n, Mat3& H) const;
  const std::vector<Vec3>& vertices() const { return vertices_; }
  /// A convex edge between two triangles whose normals differ by more than about 8°: a ridge a
  /// sheet's element side may cross between its nodes (edge contact). `out`: the mean of the
  /// two normals, unit.
  struct SharpEdge {
    int a = -1, b = -1;
    Vec3 out = Vec3::Zero();
  };
  const std::vector<SharpEdge>& sharp_edges() const { return sharp_; }
  size_t size() const { return triangles_.size(); }
  /// Every edge between exactly two triangles: the surface encloses a solid (its negative
  /// side is an inside, not only a side).
  bool closed() const { return closed_; }

 private:
  std::vector<Vec3> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Vec3> normal_;                    ///< per triangle, unit
  std::vector<std::array<Vec3, 3>> edge_side_;  ///< per triangle edge (ab, bc, ca): pseudonormal
  std::vector<Vec3> vertex_side_;               ///< per vertex: angle-weighted pseudonormal
  std::vector<contact::Box> boxes_;
  contact::FaceTree tree_;
  std::vector<SharpEdge> sharp_;
  bool closed_ = false;
};

}  // namespace velum
