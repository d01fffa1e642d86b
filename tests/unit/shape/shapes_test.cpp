// Shape functions and Gauss rules: partition of unity, derivatives against finite differences,
// Kronecker property at the Gmsh node coordinates, and the polynomial degree each rule
// integrates exactly.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <vector>

#include "../support.hpp"
#include "velum/shape/shapes.hpp"

namespace velum::shape {
namespace {

// Gmsh reference node coordinates (gmsh.info/doc/texinfo, "Node ordering"), typed here
// independently of Shape::nodes().
template <class Shape>
std::vector<std::array<double, 2>> gmsh_nodes() {
  if constexpr (std::is_same_v<Shape, Tri3>) return {{0, 0}, {1, 0}, {0, 1}};
  if constexpr (std::is_same_v<Shape, Tri6>)
    return {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
  if constexpr (std::is_same_v<Shape, Quad4>) return {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  if constexpr (std::is_same_v<Shape, Quad8>)
    return {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  if constexpr (std::is_same_v<Shape, Quad9>)
    return {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}};
  return {};
}

// Exact integral of r^a s^b over the reference domain.
template <class Shape>
double exact_monomial(int a, int b) {
  if constexpr (Shape::kNodes == 3 || Shape::kNodes == 6) {
    double num = 1, den = 1;  // a! b! / (a + b + 2)!
    for (int i = 2; i <= a; ++i) num *= i;
    for (int i = 2; i <= b; ++i) num *= i;
    for (int i = 2; i <= a + b + 2; ++i) den *= i;
    return num / den;
  } else {
    auto line = [](int p) { return p % 2 ? 0.0 : 2.0 / (p + 1); };
    return line(a) * line(b);
  }
}

// Claimed total degree (triangles) or degree per direction (quadrilaterals) of each rule.
template <class Shape>
int claimed_degree() {
  if constexpr (std::is_same_v<Shape, Tri3>) return 2;
  if constexpr (std::is_same_v<Shape, Tri6>) return 4;
  if constexpr (std::is_same_v<Shape, Quad4>) return 3;
  return 5;  // 3x3 Gauss
}

template <class Shape>
class SurfaceShape : public ::testing::Test {};
using SurfaceShapes = ::testing::Types<Tri3, Tri6, Quad4, Quad8, Quad9>;
TYPED_TEST_SUITE(SurfaceShape, SurfaceShapes);

TYPED_TEST(SurfaceShape, PartitionOfUnityAndDerivatives) {
  using S = TypeParam;
  test::Random rnd(5);
  typename S::Values N, Np, Nm;
  typename S::Derivs dN, dummy;
  double worst_fd = 0;
  for (int k = 0; k < 50; ++k) {
    double r = rnd.uniform(-1, 1), s = rnd.uniform(-1, 1);
    if (S::kNodes == 3 || S::kNodes == 6) r = 0.5 * (r + 1), s = 0.5 * (s + 1) * (1 - r);
    S::eval(r, s, N, dN);
    EXPECT_NEAR(N.sum(), 1.0, 1e-14);
    EXPECT_NEAR(dN.col(0).sum(), 0.0, 1e-13);
    EXPECT_NEAR(dN.col(1).sum(), 0.0, 1e-13);
    const double h = 1e-6;
    for (int d = 0; d < 2; ++d) {
      S::eval(r + (d == 0 ? h : 0), s + (d == 1 ? h : 0), Np, dummy);
      S::eval(r - (d == 0 ? h : 0), s - (d == 1 ? h : 0), Nm, dummy);
      const double err = ((Np - Nm) / (2 * h) - dN.col(d)).cwiseAbs().maxCoeff();
      EXPECT_LT(err, 1e-8);
      worst_fd = std::max(worst_fd, err);
    }
  }
  std::cout << S::kName << ": worst |dN - FD| = " << worst_fd << "\n";
}

TYPED_TEST(SurfaceShape, GmshNodeOrderAndKronecker) {
  using S = TypeParam;
  const auto ref = gmsh_nodes<S>();
  const auto nodes = S::nodes();
  ASSERT_EQ(static_cast<int>(ref.size()), S::kNodes);
  typename S::Values N;
  typename S::Derivs dN;
  for (int k = 0; k < S::kNodes; ++k) {
    EXPECT_EQ(nodes[k][0], ref[k][0]) << "node " << k;
    EXPECT_EQ(nodes[k][1], ref[k][1]) << "node " << k;
    S::eval(ref[k][0], ref[k][1], N, dN);
    for (int j = 0; j < S::kNodes; ++j)
      EXPECT_NEAR(N[j], j == k ? 1.0 : 0.0, 1e-15) << "N_" << j << " at node " << k;
  }
}

TYPED_TEST(SurfaceShape, GaussRuleIntegratesClaimedDegree) {
  using S = TypeParam;
  constexpr auto rule = S::rule();
  const int p = claimed_degree<S>();
  const bool tri = S::kNodes == 3 || S::kNodes == 6;
  double worst = 0;
  for (int a = 0; a <= p; ++a)
    for (int b = 0; b <= (tri ? p - a : p); ++b) {
      double q = 0;
      for (int i = 0; i < S::kPoints; ++i)
        q += rule.w[i] * std::pow(rule.xi[i][0], a) * std::pow(rule.xi[i][1], b);
      const double err = std::abs(q - exact_monomial<S>(a, b));
      EXPECT_LT(err, 1e-14) << "r^" << a << " s^" << b;
      worst = std::max(worst, err);
    }
  // ... and the rule is not exact one degree higher for some monomial (the claim is sharp).
  double miss = 0;
  for (int a = 0; a <= p + 1; ++a) {
    const int b = tri ? p + 1 - a : p + 1;
    double q = 0;
    for (int i = 0; i < S::kPoints; ++i)
      q += rule.w[i] * std::pow(rule.xi[i][0], a) * std::pow(rule.xi[i][1], b);
    miss = std::max(miss, std::abs(q - exact_monomial<S>(a, b)));
  }
  EXPECT_GT(miss, 1e-6);
  std::cout << S::kName << " rule: degree " << p << ", worst error " << worst << "\n";
}

template <class Shape>
class LineShape : public ::testing::Test {};
using LineShapes = ::testing::Types<Line2, Line3>;
TYPED_TEST_SUITE(LineShape, LineShapes);

TYPED_TEST(LineShape, PartitionDerivativesNodesAndRule) {
  using S = TypeParam;
  // Gmsh line order: ends first, then the middle node.
  const std::vector<double> nodes =
      S::kNodes == 2 ? std::vector<double>{-1, 1} : std::vector<double>{-1, 1, 0};
  typename S::Values N, dN, Np, Nm, d;
  for (int k = 0; k < S::kNodes; ++k) {
    S::eval(nodes[k], N, dN);
    for (int j = 0; j < S::kNodes; ++j) EXPECT_NEAR(N[j], j == k ? 1.0 : 0.0, 1e-15);
  }
  test::Random rnd(9);
  for (int k = 0; k < 20; ++k) {
    const double r = rnd.uniform(-1, 1), h = 1e-6;
    S::eval(r, N, dN);
    EXPECT_NEAR(N.sum(), 1.0, 1e-14);
    EXPECT_NEAR(dN.sum(), 0.0, 1e-14);
    S::eval(r + h, Np, d);
    S::eval(r - h, Nm, d);
    EXPECT_LT(((Np - Nm) / (2 * h) - dN).cwiseAbs().maxCoeff(), 1e-8);
  }
  constexpr auto rule = S::rule();
  const int p = 2 * S::kPoints - 1;
  for (int a = 0; a <= p + 1; ++a) {
    double q = 0;
    for (int i = 0; i < S::kPoints; ++i) q += rule.w[i] * std::pow(rule.xi[i][0], a);
    const double exact = a % 2 ? 0.0 : 2.0 / (a + 1);
    if (a <= p) {
      EXPECT_NEAR(q, exact, 1e-14) << "r^" << a;
    } else {
      EXPECT_GT(std::abs(q - exact), 1e-6);
    }
  }
}

}  // namespace
}  // namespace velum::shape
