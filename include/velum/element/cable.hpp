// Cable and truss element kernels (docs/theory.md) for 2- and 3-node lines: total Lagrangian
// Green strain along the axis, tension-only unless the law carries compression.
#pragma once

#include <array>

#include "velum/material/cable_law.hpp"
#include "velum/shape/shapes.hpp"

namespace velum {

template <class Shape>
struct CablePoint {
  typename Shape::Values N, dN;
  double L0sq;  ///< |X'|², reference metric
  double w;     ///< Gauss weight
  double EAw;   ///< E A w / |X'| (ready to use)
};

template <class Shape>
struct Cable {
  static constexpr int kN = Shape::kNodes;
  static constexpr int kQ = Shape::kPoints;
  static constexpr int kDofs = 3 * kN;
  using Nodes = Eigen::Matrix<double, 3, kN>;
  using Vector = Eigen::Matrix<double, kDofs, 1>;
  using Matrix = Eigen::Matrix<double, kDofs, kDofs>;
  using NodeMatrix = Eigen::Matrix<double, kN, kN>;
  using Points = std::array<CablePoint<Shape>, kQ>;

  /// Fills the points; returns the smallest |X'| (<= 0: zero-length or degenerate cable).
  static double setup(const Nodes& X, double E, double area, Points& pts,
                      shape::Integration integration = shape::Integration::kGauss);
  static void force(const Points& pts, const CableLaw& law, const Nodes& x, Vector& r);
  static void force_tangent(const Points& pts, const CableLaw& law, const Nodes& x, Vector& r,
                            Matrix& K);
  static double strain_energy(const Points& pts, const CableLaw& law, const Nodes& x);
  /// Whether the axis x' at every point of `to` is non-zero and within 90° of its direction in
  /// `from`: a line that reverses between two nearby states went through zero length.
  static bool keeps_orientation(const Points& pts, const Nodes& from, const Nodes& to);
  /// Consistent mass per unit density and area (scalar n x n).
  static NodeMatrix mass(const Points& pts);
  /// Geometric stiffness of a unit axial stress per unit area, ∫ H_N' H_M' / |X'| dξ (scalar
  /// n x n, to be multiplied by the area and I3): see Membrane::tension_stiffness.
  static NodeMatrix tension_stiffness(const Points& pts);
  /// Reference length.
  static double length(const Points& pts);
  /// Mean true (Cauchy) axial force N λ over the points (per unit E·A·... as set up).
  static double true_force(const Points& pts, const CableLaw& law, const Nodes& x);
};

}  // namespace velum
