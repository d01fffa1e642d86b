// The analytic rigid surfaces: signed distance, normal and curvature, in the body's place at
// s = 0 and carried by its motion.
#include <Eigen/Geometry>
#include <cmath>

#include "rigid_mesh.hpp"
#include "velum/load/contact_load.hpp"

namespace velum {
namespace {

Mat3 rotation_of(const Vec3& r, double s) {
  const double angle = s * r.norm();
  if (angle == 0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, r.normalized()).toRotationMatrix();
}

}  // namespace

std::shared_ptr<const RigidMesh> make_rigid_mesh(std::vector<Vec3> vertices,
                                                 std::vector<std::array<int, 3>> triangles) {
  return std::make_shared<const RigidMesh>(std::move(vertices), std::move(triangles));
}

Vec3 RigidBody::moved(const Vec3& Y, double s) const {
  return pivot + rotation_of(rotation, s) * (Y - pivot) + s * displacement;
}

Vec3 RigidBody::unmoved(const Vec3& y, double s) const {
  return pivot + rotation_of(rotation, s).transpose() * (y - s * displacement - pivot);
}

Vec3 RigidBody::position(double s) const {
  return moved(point, s);
}

double RigidBody::gap(const Vec3& x, double s, Vec3& n, Mat3& H) const {
  const Mat3 R = rotation_of(rotation, s);
  const Vec3 y = R.transpose() * (x - s * displacement - pivot) + pivot;  // at s = 0
  double g = 0;
  Vec3 n0;
  Mat3 H0 = Mat3::Zero();
  switch (shape) {
    case Shape::kPlane:
      n0 = direction;
      g = direction.dot(y - point);
      break;
    case Shape::kSphere: {
      const Vec3 d = y - point;
      const double r = d.norm();
      // At the centre any direction serves (the node is deep inside: the step will be cut).
      n0 = r > 0 ? Vec3(d / r) : Vec3::UnitZ();
      g = r - radius;
      if (r > 0) H0 = (Mat3::Identity() - n0 * n0.transpose()) / r;
      break;
    }
    case Shape::kCylinder: {
      const Vec3 w = y - point;
      const Vec3 d = w - w.dot(direction) * direction;
      const double r = d.norm();
      n0 = r > 0 ? Vec3(d / r) : direction.unitOrthogonal();
      g = r - radius;
      if (r > 0)
        H0 = (Mat3::Identity() - direction * direction.transpose() - n0 * n0.transpose()) / r;
      break;
    }
    case Shape::kMesh:
      g = mesh->gap(y, n0, H0);
      break;
  }
  n = R * n0;
  H = R * H0 * R.transpose();
  return g;
}

bool RigidBody::lies_inside(const RigidBody& other) const {
  if (other.shape == Shape::kMesh && !other.mesh->closed()) return false;
  Vec3 n;
  Mat3 H;
  switch (shape) {
    case Shape::kSphere:
      return other.gap(point, 0, n, H) <= -radius;
    case Shape::kMesh:
      for (const Vec3& v : mesh->vertices())
        if (!(other.gap(v, 0, n, H) < 0)) return false;
      return true;
    case Shape::kPlane:
    case Shape::kCylinder:
      break;  // unbounded
  }
  return false;
}

}  // namespace velum
