// Membrane element kernels (docs/theory.md), templated on the surface shape: set-up of the
// integration-point data (convected-frame stiffness computed once, total Lagrangian),
// internal force, consistent tangent (material + geometric), mass, and follower pressure with
// its load stiffness. Kernels see node positions and point data only, never global storage;
// they allocate nothing. Frames: node coordinates are global Cartesian; stresses in
// MembranePoint are contravariant convected components.
#pragma once

#include <array>

#include "velum/material/axes.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/shape/shapes.hpp"

namespace velum {

/// Shape-function values, derivatives and weights at the points of a rule: the same for every
/// element of a shape, so they are held once per rule instead of once per element point.
template <class Shape>
struct PointShapes {
  std::array<typename Shape::Values, Shape::kPoints> N;   ///< shape function values
  std::array<typename Shape::Derivs, Shape::kPoints> dN;  ///< dN/dξ (n x 2)
  std::array<double, Shape::kPoints> w;                   ///< weights in ξ
  /// The table of `integration`'s rule (built on first use, immutable after).
  static const PointShapes& of(shape::Integration integration);
};

/// What an element keeps at one integration point.
template <class Shape>
struct MembranePoint {
  Mat3 D;       ///< E^{αβγδ} in engineering Voigt, times t0 dA w (ready to use)
  Vec3 G;       ///< reference metric G11, G22, G12
  Mat2 T;       ///< T(a,α) = m_a · G^α: sheet axes in the convected frame
  double t0dA;  ///< t0 · dA · w (reference volume weight)
};

/// The strain map between the convected frame and the sheet axes at a point with
/// T(a,α) = m_a · G^α: E_sheet = A γ (both engineering Voigt), and S_convected = Aᵀ S_sheet,
/// so that a stiffness C in the sheet axes is D = Aᵀ C A in the convected frame.
Mat3 sheet_strain_map(const Mat2& T);

/// How the kernels turn a point's convected strain γ = [γ11, γ22, 2γ12] into the weighted
/// stress t0 dA w S^{αβ} and its tangent: a compile-time policy, chosen once per block.
/// `tangent` returns a reference to the weighted D (the point's own when it is constant).
///
/// The linear elastic sheet: D computed at set-up, S = D γ (the fast path).
struct ElasticPoints {
  template <class Point>
  void stress(const Point& p, const Vec3& e, Vec3& S) const {
    S.noalias() = p.D * e;
  }
  template <class Point>
  const Mat3& tangent(const Point& p, const Vec3& e, Vec3& S, Mat3&) const {
    S.noalias() = p.D * e;
    return p.D;
  }
  template <class Point>
  double energy(const Point& p, const Vec3& e) const {
    return 0.5 * e.dot(p.D * e);
  }
};

/// The linear elastic sheet with a prestress S0 (2nd PK, sheet axes): S = D γ + Aᵀ S0.
/// (The explicit step takes membrane_explicit.hpp's records, Aᵀ S0 formed once there.)
struct PrestressedPoints {
  Vec3 S0 = Vec3::Zero();
  template <class Point>
  void stress(const Point& p, const Vec3& e, Vec3& S) const {
    S.noalias() = p.D * e + p.t0dA * (sheet_strain_map(p.T).transpose() * S0);
  }
  template <class Point>
  const Mat3& tangent(const Point& p, const Vec3& e, Vec3& S, Mat3&) const {
    stress(p, e, S);
    return p.D;
  }
  template <class Point>
  double energy(const Point& p, const Vec3& e) const {
    return 0.5 * e.dot(p.D * e) + p.t0dA * S0.dot(sheet_strain_map(p.T) * e);
  }
};

/// Any sheet law that is not affine (wrinkling, nonlinear laws): the law's interface
/// (SheetLawBase) evaluated in the sheet axes at each point from the strain there, one virtual
/// call a point. ElasticPoints and PrestressedPoints are the fast path of the affine laws.
struct LawPoints {
  const SheetLaw* law = nullptr;
  template <class Point>
  SheetResponse evaluate(const Point& p, const Vec3& e) const {
    SheetResponse r;
    law->evaluate(sheet_strain_map(p.T) * e, r);
    return r;
  }
  template <class Point>
  void stress(const Point& p, const Vec3& e, Vec3& S) const {
    const Mat3 A = sheet_strain_map(p.T);
    SheetResponse r;
    law->stress(A * e, r);  // no tangent
    S.noalias() = p.t0dA * (A.transpose() * r.S);
  }
  template <class Point>
  const Mat3& tangent(const Point& p, const Vec3& e, Vec3& S, Mat3& D) const {
    const Mat3 A = sheet_strain_map(p.T);
    SheetResponse r;
    law->evaluate(A * e, r);
    S.noalias() = p.t0dA * (A.transpose() * r.S);
    D.noalias() = p.t0dA * (A.transpose() * r.C * A);
    return D;
  }
  template <class Point>
  double energy(const Point& p, const Vec3& e) const {
    return p.t0dA * law->energy(sheet_strain_map(p.T) * e);
  }
};

/// A sheet law with a history per point (plasticity): LawPoints with each point's committed
/// history. The kernels pass a point by reference into its element's array, so a point's
/// index is its offset from `first` (the element's first point); `history` points at the
/// element's first point's history, `size` doubles a point. The block sets both per element.
struct HistoryLawPoints {
  const SheetLaw* law = nullptr;
  const double* history = nullptr;
  const void* first = nullptr;
  int size = 0;
  template <class Point>
  std::span<const double> h(const Point& p) const {
    const auto q = &p - static_cast<const Point*>(first);
    return {history + q * size, static_cast<size_t>(size)};
  }
  template <class Point>
  void stress(const Point& p, const Vec3& e, Vec3& S) const {
    const Mat3 A = sheet_strain_map(p.T);
    SheetResponse r;
    law->stress(A * e, h(p), r);  // no tangent
    S.noalias() = p.t0dA * (A.transpose() * r.S);
  }
  template <class Point>
  const Mat3& tangent(const Point& p, const Vec3& e, Vec3& S, Mat3& D) const {
    const Mat3 A = sheet_strain_map(p.T);
    SheetResponse r;
    law->evaluate(A * e, h(p), r);
    S.noalias() = p.t0dA * (A.transpose() * r.S);
    D.noalias() = p.t0dA * (A.transpose() * r.C * A);
    return D;
  }
  template <class Point>
  double energy(const Point& p, const Vec3& e) const {
    return p.t0dA * law->energy(sheet_strain_map(p.T) * e, h(p));
  }
};

/// An element's integration points and the rule they belong to.
template <class Shape>
struct MembranePoints {
  /// First: the kernels read it before the points, and a record read from its head on is one
  /// the memory's prefetcher follows (at the tail, the kernel waited on memory for it).
  const PointShapes<Shape>* shapes = nullptr;  ///< set by Membrane::setup
  std::array<MembranePoint<Shape>, Shape::kPoints> at;
  MembranePoint<Shape>& operator[](int q) { return at[q]; }
  const MembranePoint<Shape>& operator[](int q) const { return at[q]; }
};

template <class Shape>
struct Membrane {
  static constexpr int kN = Shape::kNodes;
  static constexpr int kQ = Shape::kPoints;
  static constexpr int kDofs = 3 * kN;
  using Nodes = Eigen::Matrix<double, 3, kN>;      ///< node coordinates, one column per node
  using Vector = Eigen::Matrix<double, kDofs, 1>;  ///< node-major: (x1, y1, z1, x2, ...)
  using Matrix = Eigen::Matrix<double, kDofs, kDofs>;
  using NodeMatrix = Eigen::Matrix<double, kN, kN>;
  using Points = MembranePoints<Shape>;

  /// Reference tangent basis at ξ: columns G1, G2.
  static Eigen::Matrix<double, 3, 2> basis(const Nodes& X, const std::array<double, 2>& xi);

  /// Unit normal of the reference surface at the element centre (for material axes).
  static Vec3 centre_normal(const Nodes& X);

  /// Fills the integration points. Q: the law's reference stiffness
  /// (SheetLaw::reference_stiffness: the constant stiffness of an affine law) in the sector
  /// axes (m1, m2), which are projected onto the tangent plane at each point. Returns the smallest
  /// dA/dξ found, so the caller can reject degenerate or inverted elements (<= 0). Nodal
  /// integration needs Shape::kNodalRule.
  static double setup(const Nodes& X, const Mat3& Q, const SheetAxes& axes, double t0, Points& pts,
                      shape::Integration integration = shape::Integration::kGauss);

  /// Internal force r_N = t0 ∫ S^{αβ} ∂γ_αβ/∂x_N dA at current positions x, with the stress
  /// from the policy `law` (ElasticPoints, PrestressedPoints or LawPoints).
  template <class Law>
  static void force(const Points& pts, const Law& law, const Nodes& x, Vector& r);
  /// Internal force and consistent tangent dr/dx.
  template <class Law>
  static void force_tangent(const Points& pts, const Law& law, const Nodes& x, Vector& r,
                            Matrix& K);
  /// force() and pressure_force() in one pass over the points (each point's g1, g2 serve
  /// both): the same forces (the same operations in the same order).
  template <class Law>
  static void force_and_pressure(const Points& pts, const Law& law, const Nodes& x, double p,
                                 Vector& r, Vector& f);
  /// Strain energy t0 ∫ W(E) dA.
  template <class Law>
  static double strain_energy(const Points& pts, const Law& law, const Nodes& x);

  /// The linear elastic sheet (ElasticPoints).
  static void force(const Points& pts, const Nodes& x, Vector& r) {
    force(pts, ElasticPoints{}, x, r);
  }
  static void force_tangent(const Points& pts, const Nodes& x, Vector& r, Matrix& K) {
    force_tangent(pts, ElasticPoints{}, x, r, K);
  }
  static double strain_energy(const Points& pts, const Nodes& x) {
    return strain_energy(pts, ElasticPoints{}, x);
  }

  /// Green-Lagrange strain [γ11, γ22, 2γ12] at point q for the current basis g.
  static Vec3 strain(const MembranePoint<Shape>& p, const Eigen::Matrix<double, 3, 2>& g) {
    return {0.5 * (g.col(0).squaredNorm() - p.G[0]), 0.5 * (g.col(1).squaredNorm() - p.G[1]),
            g.col(0).dot(g.col(1)) - p.G[2]};
  }
  /// Whether the surface normal g1 x g2 at every point of configuration `to` is non-zero and
  /// within 90° of its direction in `from`: a surface that turns inside out between two
  /// nearby states (a step) passes through zero area on the way. Not part of the force
  /// kernels (a separate pass, once per state checked). It needs only the block's rule, not
  /// the points' records (a pass that reads them misses the cache once an element).
  static bool keeps_orientation(const PointShapes<Shape>& shapes, const Nodes& from,
                                const Nodes& to);
  /// Consistent mass per unit density (scalar n x n, to be multiplied by ρ and I3).
  static NodeMatrix mass(const Points& pts);
  /// Geometric stiffness of a uniform isotropic unit tension (2nd PK stress S^{αβ} = G^{αβ}
  /// in every direction of the reference surface) t0 ∫ G^{αβ} H_N,α H_M,β dA: the Hessian of
  /// that stress's work, a constant (scalar n x n, to be multiplied by I3). Newton's first
  /// correction from a stress-free sheet borrows it (SecondOrderSystem::stiffen_stress_free).
  static NodeMatrix tension_stiffness(const Points& pts);

  /// Green-Lagrange strain [γ11, γ22, 2γ12] and 2nd PK stress [S11, S22, S12] (contravariant
  /// convected components) at point q, and the current basis g.
  static void strain_stress(const Points& pts, int q, const Nodes& x, Vec3& e, Vec3& S,
                            Eigen::Matrix<double, 3, 2>& g);

  /// Follower pressure p on the current surface: f_N = p ∫ H_N (g1 x g2) dξ.
  static void pressure_force(const Points& pts, const Nodes& x, double p, Vector& f);
  /// ... and its load stiffness df/dx (unsymmetric).
  static void pressure_force_tangent(const Points& pts, const Nodes& x, double p, Vector& f,
                                     Matrix& K);

  /// Pressure p acting along the fixed unit direction d: f_N = p d ∫ H_N φ dξ with φ the area
  /// projected normal to d, |(g1 x g2)·d| (`projected`: snow on a roof's plan), or the
  /// current area |g1 x g2|.
  static void directed_pressure_force(const Points& pts, const Nodes& x, double p, const Vec3& d,
                                      bool projected, Vector& f);
  /// ... and its load stiffness df/dx = p d ⊗ ∫ H_N ∂φ/∂x dξ (unsymmetric).
  static void directed_pressure_force_tangent(const Points& pts, const Nodes& x, double p,
                                              const Vec3& d, bool projected, Vector& f, Matrix& K);
};

}  // namespace velum
