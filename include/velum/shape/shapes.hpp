// Isoparametric shape functions and Gauss rules for Velum's element shapes, in Gmsh node order.
// Surfaces: tri3, tri6 (natural coordinates on the unit triangle), quad4, quad8, quad9 (on
// [-1,1]^2). Lines: line2, line3 (on [-1,1], Gmsh order: ends first, then the middle node).
// Each Gauss rule integrates the consistent mass of an undistorted element exactly. Nodal
// (Lobatto) rules put the points on the nodes: the mass comes out lumped, and a quad4 of a
// fibre material becomes exactly the pin-jointed net along its edges.
#pragma once

#include <array>
#include <string_view>

#include "velum/math/types.hpp"

namespace velum::shape {

template <int Points, int Dim>
struct GaussRule {
  std::array<std::array<double, Dim>, Points> xi;
  std::array<double, Points> w;
};

/// Where an element's integration points are: Gauss (the default) or on the nodes.
enum class Integration { kGauss, kNodal };

namespace detail {
inline constexpr double kG2 = 0.57735026918962576451;  // 1/sqrt(3)
inline constexpr double kG3 = 0.77459666924148337704;  // sqrt(3/5)
inline constexpr std::array<double, 3> kG3x = {-kG3, 0.0, kG3};
inline constexpr std::array<double, 3> kG3w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

constexpr GaussRule<9, 2> quad_3x3() {
  GaussRule<9, 2> r{};
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      r.xi[3 * j + i] = {kG3x[i], kG3x[j]};
      r.w[3 * j + i] = kG3w[i] * kG3w[j];
    }
  return r;
}
}  // namespace detail

/// 3-node triangle, N = (1-r-s, r, s).
struct Tri3 {
  static constexpr int kNodes = 3, kDim = 2, kPoints = 3;
  static constexpr std::string_view kName = "tri3";
  static constexpr bool kTriangle = true;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Derivs = Eigen::Matrix<double, kNodes, 2>;
  static constexpr GaussRule<kPoints, 2> rule() {
    return {{{{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}}},
            {1.0 / 6, 1.0 / 6, 1.0 / 6}};
  }
  static constexpr bool kNodalRule = true;
  static constexpr GaussRule<kPoints, 2> nodal_rule() {
    return {{{{0, 0}, {1, 0}, {0, 1}}}, {1.0 / 6, 1.0 / 6, 1.0 / 6}};
  }
  static void eval(double r, double s, Values& N, Derivs& dN) {
    N << 1 - r - s, r, s;
    dN << -1, -1, 1, 0, 0, 1;
  }
  static constexpr std::array<std::array<double, 2>, kNodes> nodes() {
    return {{{0, 0}, {1, 0}, {0, 1}}};
  }
};

/// 6-node triangle; nodes 4-6 at the midpoints of edges 1-2, 2-3, 3-1.
struct Tri6 {
  static constexpr int kNodes = 6, kDim = 2, kPoints = 6;
  static constexpr std::string_view kName = "tri6";
  static constexpr bool kTriangle = true;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Derivs = Eigen::Matrix<double, kNodes, 2>;
  static constexpr GaussRule<kPoints, 2> rule() {
    // Strang-Fix 6-point rule, degree 4.
    constexpr double a = 0.445948490915965, b = 0.091576213509771;
    constexpr double wa = 0.223381589678011 / 2, wb = 0.109951743655322 / 2;
    return {{{{a, a}, {1 - 2 * a, a}, {a, 1 - 2 * a}, {b, b}, {1 - 2 * b, b}, {b, 1 - 2 * b}}},
            {wa, wa, wa, wb, wb, wb}};
  }
  static constexpr bool kNodalRule = false;  // a nodal rule puts zero weight on the corners
  static constexpr GaussRule<kPoints, 2> nodal_rule() { return rule(); }
  static void eval(double r, double s, Values& N, Derivs& dN) {
    const double t = 1 - r - s;
    N << t * (2 * t - 1), r * (2 * r - 1), s * (2 * s - 1), 4 * t * r, 4 * r * s, 4 * s * t;
    dN << -(4 * t - 1), -(4 * t - 1), 4 * r - 1, 0, 0, 4 * s - 1, 4 * (t - r), -4 * r, 4 * s, 4 * r,
        -4 * s, 4 * (t - s);
  }
  static constexpr std::array<std::array<double, 2>, kNodes> nodes() {
    return {{{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}}};
  }
};

/// 4-node bilinear quadrilateral.
struct Quad4 {
  static constexpr int kNodes = 4, kDim = 2, kPoints = 4;
  static constexpr std::string_view kName = "quad4";
  static constexpr bool kTriangle = false;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Derivs = Eigen::Matrix<double, kNodes, 2>;
  static constexpr GaussRule<kPoints, 2> rule() {
    using detail::kG2;
    return {{{{-kG2, -kG2}, {kG2, -kG2}, {kG2, kG2}, {-kG2, kG2}}}, {1, 1, 1, 1}};
  }
  static constexpr bool kNodalRule = true;
  static constexpr GaussRule<kPoints, 2> nodal_rule() {
    return {{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}}, {1, 1, 1, 1}};
  }
  static void eval(double r, double s, Values& N, Derivs& dN) {
    N << 0.25 * (1 - r) * (1 - s), 0.25 * (1 + r) * (1 - s), 0.25 * (1 + r) * (1 + s),
        0.25 * (1 - r) * (1 + s);
    dN << -0.25 * (1 - s), -0.25 * (1 - r), 0.25 * (1 - s), -0.25 * (1 + r), 0.25 * (1 + s),
        0.25 * (1 + r), -0.25 * (1 + s), 0.25 * (1 - r);
  }
  static constexpr std::array<std::array<double, 2>, kNodes> nodes() {
    return {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  }
};

/// 8-node serendipity quadrilateral; nodes 5-8 at the midpoints of edges 1-2, 2-3, 3-4, 4-1.
struct Quad8 {
  static constexpr int kNodes = 8, kDim = 2, kPoints = 9;
  static constexpr std::string_view kName = "quad8";
  static constexpr bool kTriangle = false;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Derivs = Eigen::Matrix<double, kNodes, 2>;
  static constexpr GaussRule<kPoints, 2> rule() { return detail::quad_3x3(); }
  static constexpr bool kNodalRule = false;  // Lobatto's centre point is not a node
  static constexpr GaussRule<kPoints, 2> nodal_rule() { return rule(); }
  static void eval(double r, double s, Values& N, Derivs& dN) {
    constexpr double rc[4] = {-1, 1, 1, -1}, sc[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
      const double a = rc[i], b = sc[i], ra = 1 + a * r, sb = 1 + b * s;
      N[i] = 0.25 * ra * sb * (a * r + b * s - 1);
      dN(i, 0) = 0.25 * a * sb * (2 * a * r + b * s);
      dN(i, 1) = 0.25 * b * ra * (a * r + 2 * b * s);
    }
    N[4] = 0.5 * (1 - r * r) * (1 - s), dN(4, 0) = -r * (1 - s), dN(4, 1) = -0.5 * (1 - r * r);
    N[5] = 0.5 * (1 + r) * (1 - s * s), dN(5, 0) = 0.5 * (1 - s * s), dN(5, 1) = -(1 + r) * s;
    N[6] = 0.5 * (1 - r * r) * (1 + s), dN(6, 0) = -r * (1 + s), dN(6, 1) = 0.5 * (1 - r * r);
    N[7] = 0.5 * (1 - r) * (1 - s * s), dN(7, 0) = -0.5 * (1 - s * s), dN(7, 1) = -(1 - r) * s;
  }
  static constexpr std::array<std::array<double, 2>, kNodes> nodes() {
    return {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}}};
  }
};

/// 9-node Lagrange quadrilateral; Gmsh order: corners, edge midpoints, centre.
struct Quad9 {
  static constexpr int kNodes = 9, kDim = 2, kPoints = 9;
  static constexpr std::string_view kName = "quad9";
  static constexpr bool kTriangle = false;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Derivs = Eigen::Matrix<double, kNodes, 2>;
  static constexpr GaussRule<kPoints, 2> rule() { return detail::quad_3x3(); }
  static constexpr bool kNodalRule = true;
  static constexpr GaussRule<kPoints, 2> nodal_rule() {  // 3x3 Lobatto (Simpson), Gmsh order
    constexpr double c = 1.0 / 9, e = 4.0 / 9, m = 16.0 / 9;
    return {{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}}},
            {c, c, c, c, e, e, e, e, m}};
  }
  static void eval(double r, double s, Values& N, Derivs& dN) {
    // 1-D quadratic Lagrange at -1, 0, 1 and the tensor product in Gmsh order.
    const double l[3] = {0.5 * r * (r - 1), 1 - r * r, 0.5 * r * (r + 1)};
    const double dl[3] = {r - 0.5, -2 * r, r + 0.5};
    const double m[3] = {0.5 * s * (s - 1), 1 - s * s, 0.5 * s * (s + 1)};
    const double dm[3] = {s - 0.5, -2 * s, s + 0.5};
    constexpr int ir[9] = {0, 2, 2, 0, 1, 2, 1, 0, 1}, is[9] = {0, 0, 2, 2, 0, 1, 2, 1, 1};
    for (int i = 0; i < 9; ++i) {
      N[i] = l[ir[i]] * m[is[i]];
      dN(i, 0) = dl[ir[i]] * m[is[i]];
      dN(i, 1) = l[ir[i]] * dm[is[i]];
    }
  }
  static constexpr std::array<std::array<double, 2>, kNodes> nodes() {
    return {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}}};
  }
};

/// 2-node line on [-1, 1].
struct Line2 {
  static constexpr int kNodes = 2, kDim = 1, kPoints = 2;
  static constexpr std::string_view kName = "cable2";
  using Values = Eigen::Matrix<double, kNodes, 1>;
  static constexpr GaussRule<kPoints, 1> rule() {
    return {{{{-detail::kG2}, {detail::kG2}}}, {1, 1}};
  }
  static constexpr bool kNodalRule = true;
  static constexpr GaussRule<kPoints, 1> nodal_rule() { return {{{{-1}, {1}}}, {1, 1}}; }
  static void eval(double r, Values& N, Values& dN) {
    N << 0.5 * (1 - r), 0.5 * (1 + r);
    dN << -0.5, 0.5;
  }
};

/// 3-node line on [-1, 1]; Gmsh order: ends, then the middle node.
struct Line3 {
  static constexpr int kNodes = 3, kDim = 1, kPoints = 3;
  static constexpr std::string_view kName = "cable3";
  using Values = Eigen::Matrix<double, kNodes, 1>;
  static constexpr GaussRule<kPoints, 1> rule() {
    using detail::kG3;
    return {{{{-kG3}, {0.0}, {kG3}}}, {5.0 / 9, 8.0 / 9, 5.0 / 9}};
  }
  static constexpr bool kNodalRule = true;
  static constexpr GaussRule<kPoints, 1> nodal_rule() {  // Simpson, Gmsh order
    return {{{{-1}, {1}, {0}}}, {1.0 / 3, 1.0 / 3, 4.0 / 3}};
  }
  static void eval(double r, Values& N, Values& dN) {
    N << 0.5 * r * (r - 1), 0.5 * r * (r + 1), 1 - r * r;
    dN << r - 0.5, r + 0.5, -2 * r;
  }
};

/// The rule of `Shape` for the given integration (kNodal only where Shape::kNodalRule).
template <class Shape>
constexpr auto rule_of(Integration integration) {
  return integration == Integration::kNodal ? Shape::nodal_rule() : Shape::rule();
}

}  // namespace velum::shape
