// VERIFICATION A6, the patch test: small distorted meshes of each surface shape in a tilted
// plane, all nodes moved by x = F X with a random 3x3 F. At every integration point the 2nd PK
// stress equals the law at E = ½(FᵀF − I) (compared in the sheet axes), and the summed element
// forces vanish at every interior node.
#include <gtest/gtest.h>

#include <iostream>
#include <vector>

#include "../support.hpp"
#include "velum/element/membrane.hpp"

namespace velum {
namespace {

using shape::Quad4;
using shape::Quad8;
using shape::Quad9;
using shape::Tri3;
using shape::Tri6;

template <class Shape>
struct PatchMesh {
  std::vector<Vec2> points;
  std::vector<bool> boundary;
  std::vector<std::array<int, Shape::kNodes>> elements;
};

// n x n cells on [0, L]^2; quadratic shapes use a lattice of half the spacing. Interior
// lattice points are perturbed by up to `distort` of the lattice spacing.
template <class Shape>
PatchMesh<Shape> make_mesh(int n, double L, double distort, test::Random& rnd) {
  constexpr bool quadratic = Shape::kNodes > 4;
  const int sub = quadratic ? 2 : 1, m = n * sub;
  const double d = L / m;
  PatchMesh<Shape> mesh;
  auto id = [m](int i, int j) { return j * (m + 1) + i; };
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) {
      const bool bnd = i == 0 || j == 0 || i == m || j == m;
      Vec2 p(i * d, j * d);
      if (!bnd) p += distort * d * Vec2(rnd.uniform(-1, 1), rnd.uniform(-1, 1));
      mesh.points.push_back(p);
      mesh.boundary.push_back(bnd);
    }
  for (int cj = 0; cj < n; ++cj)
    for (int ci = 0; ci < n; ++ci) {
      const int i = sub * ci, j = sub * cj;
      auto P = [&](int di, int dj) { return id(i + di, j + dj); };
      if constexpr (std::is_same_v<Shape, Tri3>) {
        mesh.elements.push_back({P(0, 0), P(1, 0), P(1, 1)});
        mesh.elements.push_back({P(0, 0), P(1, 1), P(0, 1)});
      } else if constexpr (std::is_same_v<Shape, Quad4>) {
        mesh.elements.push_back({P(0, 0), P(1, 0), P(1, 1), P(0, 1)});
      } else if constexpr (std::is_same_v<Shape, Tri6>) {
        mesh.elements.push_back({P(0, 0), P(2, 0), P(2, 2), P(1, 0), P(2, 1), P(1, 1)});
        mesh.elements.push_back({P(0, 0), P(2, 2), P(0, 2), P(1, 1), P(1, 2), P(0, 1)});
      } else if constexpr (std::is_same_v<Shape, Quad8>) {
        mesh.elements.push_back(
            {P(0, 0), P(2, 0), P(2, 2), P(0, 2), P(1, 0), P(2, 1), P(1, 2), P(0, 1)});
      } else {
        mesh.elements.push_back(
            {P(0, 0), P(2, 0), P(2, 2), P(0, 2), P(1, 0), P(2, 1), P(1, 2), P(0, 1), P(1, 1)});
      }
    }
  return mesh;
}

// Distorted but not degenerate: at every integration point dA/dξ stays above a third of its
// value in the undistorted mesh (a nearly singular metric would measure conditioning instead).
template <class Shape>
bool acceptable(const PatchMesh<Shape>& mesh, double cell) {
  const double nominal = (Shape::kNodes == 3 || Shape::kNodes == 6) ? cell * cell : cell * cell / 4;
  for (const auto& el : mesh.elements) {
    typename Membrane<Shape>::Nodes X;
    for (int k = 0; k < Shape::kNodes; ++k)
      X.col(k) = Vec3(mesh.points[el[k]].x(), mesh.points[el[k]].y(), 0);
    typename Membrane<Shape>::Points pts;
    if (Membrane<Shape>::setup(X, Mat3::Identity(), SheetAxes{}, 1.0, pts) < nominal / 3)
      return false;
  }
  return true;
}

template <class Shape>
class PatchTest : public ::testing::Test {};
using SurfaceShapes = ::testing::Types<Tri3, Tri6, Quad4, Quad8, Quad9>;
TYPED_TEST_SUITE(PatchTest, SurfaceShapes);

TYPED_TEST(PatchTest, A6HomogeneousDeformationIsReproduced) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(600 + S::kNodes);
  const double t0 = 0.05;
  for (const auto& [label, law] : test::test_laws()) {
    double worst_S = 0, worst_f = 0;
    for (int trial = 0; trial < 3; ++trial) {
      PatchMesh<S> mesh;
      int tries = 0;
      do {
        mesh = make_mesh<S>(3, 2.0, 0.25, rnd);
      } while (!acceptable(mesh, 2.0 / 3) && ++tries < 100);
      ASSERT_LT(tries, 100) << "no acceptable distorted mesh";
      // The sheet in a tilted plane, axes at 30 degrees in it.
      const Mat3 R0 = rnd.rotation(rnd.uniform(0, 3));
      const Vec3 c0 = rnd.vec3(-1, 1);
      const SheetAxes axes = test::axes_at(30, R0);
      const Mat3 F = Mat3::Identity() + 0.3 * rnd.mat3(-1, 1);
      // Reference solution in the sheet axes.
      const Eigen::Matrix<double, 3, 2> Fm =
          F * (Eigen::Matrix<double, 3, 2>() << axes.m1, axes.m2).finished();
      const Mat2 E = 0.5 * (Fm.transpose() * Fm - Mat2::Identity());
      const Vec3 S_ref = law.stress(Vec3(E(0, 0), E(1, 1), 2 * E(0, 1)));
      const double S_scale = S_ref.cwiseAbs().maxCoeff();

      const int np = static_cast<int>(mesh.points.size());
      Eigen::Matrix<double, 3, Eigen::Dynamic> f = Eigen::MatrixXd::Zero(3, np);
      double f_scale = 0;
      std::vector<bool> used(np, false);
      for (const auto& el : mesh.elements) {
        for (const int k : el) used[k] = true;
        typename M::Nodes X, x;
        for (int k = 0; k < S::kNodes; ++k) {
          const Vec2& p = mesh.points[el[k]];
          X.col(k) = R0 * Vec3(p.x(), p.y(), 0) + c0;
          x.col(k) = F * X.col(k);
        }
        typename M::Points pts;
        ASSERT_GT(M::setup(X, law.Q(), axes, t0, pts), 0) << "inverted element in the mesh";
        for (int q = 0; q < S::kPoints; ++q) {
          Vec3 e, Sc;
          Eigen::Matrix<double, 3, 2> g;
          M::strain_stress(pts, q, x, e, Sc, g);
          // Contravariant S^{αβ} to the sheet axes: S_ab = S^{αβ} (m_a·G_α)(m_b·G_β).
          const Eigen::Matrix<double, 3, 2> G = X * pts.shapes->dN[q];
          Mat2 Sm;
          Sm << Sc[0], Sc[2], Sc[2], Sc[1];
          Mat2 A;  // A(a, α) = m_a · G_α
          A << axes.m1.dot(G.col(0)), axes.m1.dot(G.col(1)), axes.m2.dot(G.col(0)),
              axes.m2.dot(G.col(1));
          const Mat2 Sab = A * Sm * A.transpose();
          worst_S = std::max(
              worst_S,
              (Vec3(Sab(0, 0), Sab(1, 1), Sab(0, 1)) - S_ref).cwiseAbs().maxCoeff() / S_scale);
        }
        typename M::Vector r;
        M::force(pts, x, r);
        for (int k = 0; k < S::kNodes; ++k) {
          f.col(el[k]) += r.template segment<3>(3 * k);
          f_scale = std::max(f_scale, r.template segment<3>(3 * k).norm());
        }
      }
      int interior = 0;
      for (int i = 0; i < np; ++i) {
        if (mesh.boundary[i] || !used[i]) continue;  // lattice centres are unused by quad8
        worst_f = std::max(worst_f, f.col(i).norm() / f_scale);
        ++interior;
      }
      EXPECT_GE(interior, 4);
    }
    EXPECT_LT(worst_S, 1e-12) << S::kName << " " << label;
    EXPECT_LT(worst_f, 1e-12) << S::kName << " " << label;
    std::cout << "A6 " << S::kName << " " << label << ": worst relative error of S against the law "
              << worst_S << ", worst interior-node force / largest element node force " << worst_f
              << "\n";
  }
}

}  // namespace
}  // namespace velum
