// The explicit step's membrane kernel for affine sheet laws (linear elastic, with or without a
// prestress): internal and follower-pressure forces from a compact per-element record laid out
// point-minor (each quantity of every point side by side), so the kernel takes all of an
// element's points at once. The same forces as Membrane::force_and_pressure to round-off; the
// implicit passes never use it. Frames and units as membrane.hpp; allocates nothing.
#pragma once

#include "velum/element/membrane.hpp"

namespace velum {

/// Points of the explicit record: a linear triangle's, which see one strain, merged into one.
template <class Shape>
inline constexpr int kExplicitPoints = Shape::kNodes == 3 ? 1 : Shape::kPoints;

/// The shape-function data of a rule for the explicit kernel: dN[a][n][q] = ∂N_n/∂ξ_a at
/// point q, and the pressure weights pw[n][q] = Σ w N_n over the rule's points merged into q.
template <class Shape>
struct ExplicitShapes {
  static constexpr int kQ = kExplicitPoints<Shape>;
  std::array<std::array<std::array<double, kQ>, Shape::kNodes>, 2> dN;
  std::array<std::array<double, kQ>, Shape::kNodes> pw;
  /// The table of `integration`'s rule (built on first use, immutable after).
  static const ExplicitShapes& of(shape::Integration integration);
};

/// One element's explicit record: rows D11 D22 D33 D12 D13 D23 (the weighted t0 dA w D of
/// membrane.hpp, symmetric), G11 G22 G12 (reference metric), c1 c2 c3 (the weighted prestress
/// t0 dA w Aᵀ S0 in the convected frame; zero without one), each row over the points.
template <class Shape>
struct alignas(12 * kExplicitPoints<Shape> * sizeof(double) % 64 == 0 ? 64 : 32) ExplicitPoints {
  static constexpr int kQ = kExplicitPoints<Shape>;
  static constexpr int kRows = 12;
  std::array<std::array<double, kQ>, kRows> row;
};

template <class Shape>
struct MembraneExplicit {
  using M = Membrane<Shape>;
  using Nodes = typename M::Nodes;

  /// The record of an element from its points (Membrane::setup) and the prestress S0 (2nd PK,
  /// sheet axes; zero for none).
  static void record(const typename M::Points& pts, const Vec3& S0, ExplicitPoints<Shape>& out);

  /// Internal forces r (one column per node) at positions x and, when kPressure, the follower
  /// pressure p's forces f.
  template <bool kPressure>
  static void force(const ExplicitShapes<Shape>& s, const ExplicitPoints<Shape>& pts,
                    const Nodes& x, double p, Nodes& r, Nodes& f);
};

}  // namespace velum
