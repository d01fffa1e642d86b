#include "velum/material/axes.hpp"

#include <cmath>
#include <stdexcept>

namespace velum {

SheetAxes axes_from_points(const Vec3& P1, const Vec3& P2, const Vec3& P3) {
  const Vec3 d1 = P2 - P1;
  const Vec3 d3 = d1.cross(P3 - P1);
  const double scale = std::max({d1.norm(), (P3 - P1).norm(), 1e-300});
  if (d1.norm() <= 1e-12 * scale || d3.norm() <= 1e-12 * scale * scale)
    throw std::invalid_argument("axis points P1, P2, P3 are coincident or collinear");
  const Vec3 d2 = d3.cross(d1);
  return {d1.normalized(), d2.normalized(), d3.normalized()};
}

SheetAxes project_axes(const SheetAxes& sector, const Vec3& n, double* quality) {
  Vec3 m1 = sector.m1 - sector.m1.dot(n) * n;
  double q = m1.norm();
  if (q < 1e-8) {  // m1 normal to the surface: keep m2 of the sector instead
    const Vec3 m2 = sector.m2 - sector.m2.dot(n) * n;
    q = 0;
    m1 = m2.cross(n);
  }
  if (quality) *quality = q;
  m1.normalize();
  return {m1, n.cross(m1), n};
}

SheetAxes default_axes(const Vec3& n) {
  const Vec3 ref = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  Vec3 m1 = (ref - ref.dot(n) * n).normalized();
  return {m1, n.cross(m1), n};
}

}  // namespace velum
