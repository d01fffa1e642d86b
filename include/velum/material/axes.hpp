// Principal material axes of a sheet (docs/theory.md): from three points P1, P2, P3, and their
// projection onto an element's reference tangent plane so that fibres lie in the surface.
#pragma once

#include "velum/math/types.hpp"

namespace velum {

/// Orthonormal sheet axes m1, m2 (in the sheet) and the sheet normal m3, in global Cartesian.
struct SheetAxes {
  Vec3 m1 = Vec3::UnitX(), m2 = Vec3::UnitY(), m3 = Vec3::UnitZ();
};

/// d1 = P2 - P1, d3 = d1 x (P3 - P1), d2 = d3 x d1. Throws std::invalid_argument when the
/// points are coincident or collinear.
SheetAxes axes_from_points(const Vec3& P1, const Vec3& P2, const Vec3& P3);

/// Axes in the tangent plane with unit normal n: m1 projected onto the plane, m2 = n x m1.
/// `quality` receives |projection of m1| (1: the plane is the sector plane; small: poor).
/// When the projection vanishes, m2 of the sector is projected instead.
SheetAxes project_axes(const SheetAxes& sector, const Vec3& n, double* quality = nullptr);

/// The default when a section gives no axes: global x (or y when x is nearly normal to the
/// surface) projected onto the tangent plane.
SheetAxes default_axes(const Vec3& n);

}  // namespace velum
