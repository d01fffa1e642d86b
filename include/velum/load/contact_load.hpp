// Contact of membrane and cable nodes with a rigid body (the model's `contact:` entries against
// its `rigid_bodies:`, docs/contact.md): a penalty on the penetration of each node of the set
// beyond its contact thickness, augmented (Lagrange) at every accepted step, with Coulomb
// friction regularised by a tangential penalty on the slip since the last accepted step.
// Units the model's; positions and forces in the global frame.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

class RigidMesh;

/// A rigid surface of triangles (quads given split in two), the solid on the side opposite
/// their normals (right-hand rule on the corners' order). Throws std::invalid_argument on an
/// empty mesh or a degenerate triangle (its message counts the triangles from 1).
std::shared_ptr<const RigidMesh> make_rigid_mesh(std::vector<Vec3> vertices,
                                                 std::vector<std::array<int, 3>> triangles);

/// A rigid surface: a plane (solid on the side opposite its normal), a sphere or a circular
/// cylinder (solid inside), or a mesh of triangles, moved by a prescribed motion: y = pivot +
/// R(s)(Y − pivot) + s·displacement at s = function(t), R(s) the rotation by s·rotation (a rotation
/// vector, radians).
struct RigidBody {
  enum class Shape { kPlane, kSphere, kCylinder, kMesh };
  std::string name;
  Shape shape = Shape::kPlane;
  Vec3 point = Vec3::Zero();       ///< plane point, sphere centre, point on the axis, mesh centroid
  Vec3 direction = Vec3::UnitZ();  ///< plane normal (out of the solid), cylinder axis; unit
  double radius = 0;               ///< sphere, cylinder
  Vec3 displacement = Vec3::Zero();       ///< motion: translation at s = 1
  Vec3 rotation = Vec3::Zero();           ///< motion: rotation vector at s = 1 (radians)
  Vec3 pivot = Vec3::Zero();              ///< motion: the point the rotation turns about
  int function = -1;                      ///< motion: time function s(t), -1: s = 1
  std::shared_ptr<const RigidMesh> mesh;  ///< kMesh: its triangles at s = 0
  /// A free body that rotates (ContactLoad::body_node >= 0): its inertia about the centre of
  /// mass (the body node) in the global axes at t = 0; zero: it translates only.
  Mat3 inertia = Mat3::Zero();
  Vec3 angular_velocity = Vec3::Zero();  ///< initial (rad/s, global axes), with an inertia
  /// The largest distance of the surface from the centre of mass (the explicit stable step of
  /// a rotating body; sphere: the radius plus the centre's offset).
  double reach = 0;

  /// Signed distance of x from the surface with the body moved by s (positive outside), its
  /// outward unit normal n = ∇g and the Hessian H = ∇∇g (the normal's rate).
  double gap(const Vec3& x, double s, Vec3& n, Mat3& H) const;
  /// The body's point (plane point, centre, axis point) moved by s.
  Vec3 position(double s) const;
  /// Where the body point that sits at Y when s = 0 is at s.
  Vec3 moved(const Vec3& Y, double s) const;
  /// Back from the body moved by s to its place at s = 0.
  Vec3 unmoved(const Vec3& y, double s) const;
  /// Whether this body lies wholly inside `other` at s = 0 (bad input: no sheet can reach
  /// it). Only a bounded body (sphere, mesh) can, and only inside a body with an inside (a
  /// plane's half-space, a sphere, a cylinder, a closed mesh): a sphere whose centre is at
  /// least its radius deep (the signed distance changes no faster than the point moves), a
  /// mesh whose every vertex is inside.
  bool lies_inside(const RigidBody& other) const;
};

struct ContactLoad {
  int index = 0;  ///< among the model's contact entries, from 0
  RigidBody body;
  struct Part {
    int block = -1;
    std::vector<int> elements;  ///< indices into the block
  };
  std::vector<Part> parts;  ///< the element set (membranes and cables)
  std::vector<int> nodes;   ///< its nodes (set_up)
  /// Contact thickness of every node; < 0: half the section thickness of its membranes
  /// (0 for cables).
  double thickness = -1;
  double friction = 0;       ///< Coulomb coefficient
  double penalty_scale = 1;  ///< times the automatic penalty (docs/contact.md)
  /// Normal damping while in touch, as a fraction of the critical damping of the node's mass on
  /// its penalty (c = 2 ζ √(k m)); rigid bodies only. 0: the penalty is elastic.
  double damping = 0;
  bool augmented = true;  ///< Lagrange multiplier updated at every accepted step
  /// A free body (mass): the model's node that carries it (a point mass at body.point, its
  /// displacement the body's translation); -1: the body moves as prescribed.
  int body_node = -1;
  /// Sheet–sheet contact (docs/contact.md): the second element set (nodes of each set against
  /// the faces of the other); empty with a rigid body or `self`.
  std::vector<Part> other;
  bool self = false;  ///< the set's nodes against its own faces away from them (folds)
  /// Edges against edges too (where they cross between nodes), besides node to face: the
  /// sheets' sides against each other's, or against a rigid mesh's sharp edges.
  bool edges = false;
  /// Initial penetrations (sheets and rigid bodies): relaxed over this many accepted steps
  /// (0: pushed out at once).
  int relax_steps = 0;
};

std::unique_ptr<Load> make_load(ContactLoad p);

}  // namespace velum
