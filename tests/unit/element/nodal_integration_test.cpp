// Nodal (Lobatto) integration of membranes and cables (section key `integration: nodal`):
// the same FD checks as Gauss points (A4), lumped mass (A7), the patch property under affine
// motion, and the identity the woven-network verification rests on: a quad4 of two fibre
// families along its edges is exactly the pin-jointed net of its four edges, each carrying
// half the cell's thickness times its width, for any deformation.
#include <gtest/gtest.h>

#include <iostream>

#include "../support.hpp"
#include "velum/element/cable.hpp"
#include "velum/element/membrane.hpp"

namespace velum {
namespace {

using shape::Integration;

template <class Shape>
class NodalMembrane : public ::testing::Test {};
using NodalShapes = ::testing::Types<shape::Tri3, shape::Quad4, shape::Quad9>;
TYPED_TEST_SUITE(NodalMembrane, NodalShapes);

TYPED_TEST(NodalMembrane, TangentAndEnergyGradientMatchFiniteDifferences) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(300 + S::kNodes);
  for (const auto& [label, law] : test::test_laws()) {
    double worst = 0;
    for (int trial = 0; trial < 3; ++trial) {
      const Mat3 R = rnd.rotation(rnd.uniform(0, 3));
      const auto X = test::distorted_element<S>(rnd, 1.3, 0.08, 0.1 * trial, R, rnd.vec3(-2, 2));
      typename M::Points pts;
      ASSERT_GT(
          M::setup(X, law.Q(), test::axes_at(20.0 * trial, R), 0.02, pts, Integration::kNodal), 0);
      const Mat3 F = Mat3::Identity() + 0.2 * rnd.mat3(-1, 1);
      typename M::Nodes x;
      for (int n = 0; n < S::kNodes; ++n) x.col(n) = F * X.col(n) + 0.1 * rnd.vec3(-1, 1);
      typename M::Vector r;
      typename M::Matrix K;
      M::force_tangent(pts, x, r, K);
      const auto Kfd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
          x, 1.3e-6,
          [&](const typename M::Nodes& y, typename M::Vector& f) { M::force(pts, y, f); });
      const auto rfd = test::fd_gradient<typename M::Vector>(
          x, 1.3e-6, [&](const typename M::Nodes& y) { return M::strain_energy(pts, y); });
      worst = std::max({worst, test::rel_max_error(K, Kfd), test::rel_max_error(rfd, r)});
    }
    EXPECT_LT(worst, 1e-6) << S::kName << " " << label;
    std::cout << "nodal " << S::kName << " " << label << ": worst FD error " << worst << "\n";
  }
}

TYPED_TEST(NodalMembrane, MassIsLumpedAndExact) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(310 + S::kNodes);
  const auto X = test::distorted_element<S>(rnd, 1.0, 0.05, 0.0, Mat3::Identity(), Vec3::Zero());
  typename M::Points gauss, nodal;
  const auto law = PlaneStressLaw::isotropic("iso", 1, 0.3);
  M::setup(X, law.Q(), SheetAxes{}, 0.5, gauss);
  M::setup(X, law.Q(), SheetAxes{}, 0.5, nodal, Integration::kNodal);
  const auto Mg = M::mass(gauss), Mn = M::mass(nodal);
  const double off =
      (Mn - typename M::NodeMatrix(Mn.diagonal().asDiagonal())).cwiseAbs().maxCoeff();
  EXPECT_LT(off, 1e-15) << "nodal mass must be diagonal";
  EXPECT_GT(Mn.diagonal().minCoeff(), 0.0);
  EXPECT_NEAR(Mn.sum(), Mg.sum(), 1e-14 * Mg.sum()) << "total mass";
}

// Affine motion of a flat distorted element: constant strain, and the nodal rule integrates
// the resulting nodal forces exactly (the patch test's requirement), so they equal Gauss's.
TYPED_TEST(NodalMembrane, AffineMotionGivesTheGaussForces) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(320 + S::kNodes);
  // quad9: straight sides (mid-nodes at the middles), else the mapping is not bilinear.
  const double distort = S::kNodes == 9 ? 0.0 : 0.1;
  auto X = test::distorted_element<S>(rnd, 1.0, distort, 0.0, Mat3::Identity(), Vec3::Zero());
  const auto law = PlaneStressLaw::orthotropic("ortho", 2000.0, 700.0, 0.35, 300.0, false);
  typename M::Points gauss, nodal;
  M::setup(X, law.Q(), test::axes_at(25, Mat3::Identity()), 0.1, gauss);
  M::setup(X, law.Q(), test::axes_at(25, Mat3::Identity()), 0.1, nodal, Integration::kNodal);
  const Mat3 F = Mat3::Identity() + 0.3 * rnd.mat3(-1, 1);
  const typename M::Nodes x = F * X;
  typename M::Vector rg, rn;
  M::force(gauss, x, rg);
  M::force(nodal, x, rn);
  EXPECT_LT(test::rel_max_error(rn, rg), 1e-12) << S::kName;
}

TEST(NodalQuad4, FibreCellIsThePinJointedNetOfItsEdges) {
  using M = Membrane<shape::Quad4>;
  using C = Cable<shape::Line2>;
  constexpr double a = 0.7, b = 0.4, t = 0.3, E1 = 2.0e3, E2 = 5.0e2;
  M::Nodes X;
  X << 0, a, a, 0, 0, 0, b, b, 0, 0, 0, 0;
  const auto law = PlaneStressLaw::fibers("net", {{E1, 0.0}, {E2, 90.0}});
  M::Points pts;
  M::setup(X, law.Q(), SheetAxes{}, t, pts, Integration::kNodal);
  // Edges (node pairs), modulus and area: x-edges carry t b / 2, y-edges t a / 2.
  struct Edge {
    int i, j;
    double E, A;
  };
  const Edge edges[4] = {
      {0, 1, E1, t * b / 2}, {3, 2, E1, t * b / 2}, {0, 3, E2, t * a / 2}, {1, 2, E2, t * a / 2}};
  test::Random rnd(330);
  double worst = 0;
  for (int trial = 0; trial < 5; ++trial) {
    // Large and out-of-plane: stretch to 1.5, fold and twist the cell.
    const Mat3 R = rnd.rotation(3.0);
    M::Nodes x;
    for (int n = 0; n < 4; ++n) x.col(n) = R * (X.col(n) + 0.4 * rnd.vec3(-1, 1));
    M::Vector r;
    M::Matrix K;
    M::force_tangent(pts, x, r, K);
    M::Vector rnet = M::Vector::Zero();
    M::Matrix Knet = M::Matrix::Zero();
    double Unet = 0;
    for (const auto& e : edges) {
      C::Nodes Xe, xe;
      Xe << X.col(e.i), X.col(e.j);
      xe << x.col(e.i), x.col(e.j);
      C::Points cp;
      C::setup(Xe, e.E, e.A, cp);
      const CableLaw cl{e.E, true};
      C::Vector rc;
      C::Matrix Kc;
      C::force_tangent(cp, cl, xe, rc, Kc);
      Unet += C::strain_energy(cp, cl, xe);
      const int dof[2] = {3 * e.i, 3 * e.j};
      for (int p = 0; p < 2; ++p) {
        rnet.segment<3>(dof[p]) += rc.segment<3>(3 * p);
        for (int q = 0; q < 2; ++q)
          Knet.block<3, 3>(dof[p], dof[q]) += Kc.block<3, 3>(3 * p, 3 * q);
      }
    }
    worst = std::max({worst, test::rel_max_error(r, rnet), test::rel_max_error(K, Knet),
                      std::abs(M::strain_energy(pts, x) - Unet) / Unet});
  }
  EXPECT_LT(worst, 1e-13);
  std::cout << "nodal quad4 fibre cell against its edge net: worst relative difference " << worst
            << "\n";
}

TEST(NodalCable, MassIsLumpedAndStiffnessUnchanged) {
  test::Random rnd(340);
  {
    using C = Cable<shape::Line2>;
    C::Nodes X, x;
    X << Vec3(0, 0, 0), Vec3(1.2, 0.3, -0.2);
    x = X + 0.2 * C::Nodes::Random();
    C::Points g, n;
    C::setup(X, 100.0, 0.01, g);
    C::setup(X, 100.0, 0.01, n, Integration::kNodal);
    const auto Mn = C::mass(n);
    EXPECT_NEAR(Mn(0, 1), 0.0, 1e-16);
    EXPECT_NEAR(Mn.sum(), C::mass(g).sum(), 1e-15);
    C::Vector rg, rn;
    const CableLaw law{100.0, false};
    C::force(g, law, x, rg);
    C::force(n, law, x, rn);
    EXPECT_LT(test::rel_max_error(rn, rg), 1e-14) << "constant strain: any rule";
  }
  {
    using C = Cable<shape::Line3>;
    C::Nodes X;
    X << Vec3(0, 0, 0), Vec3(1.0, 0, 0), Vec3(0.5, 0, 0);  // straight: both rules exact
    C::Points g, n;
    C::setup(X, 100.0, 0.01, g);
    C::setup(X, 100.0, 0.01, n, Integration::kNodal);
    const auto Mn = C::mass(n);
    EXPECT_LT((Mn - C::NodeMatrix(Mn.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 1e-16);
    EXPECT_NEAR(Mn.sum(), C::mass(g).sum(), 1e-12);
  }
}

}  // namespace
}  // namespace velum
