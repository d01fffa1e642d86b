// Cable kernels: VERIFICATION A4 (tangent and energy gradient against central finite
// differences, taut, truss in compression, slack), A5 (rigid motion) and A7 (mass), and the
// true axial force N λ; the geometric stiffness of a unit tension.
#include <gtest/gtest.h>

#include <iostream>

#include "../support.hpp"
#include "velum/element/cable.hpp"

namespace velum {
namespace {

using shape::Line2;
using shape::Line3;

template <class Shape>
class CableKernel : public ::testing::Test {};
using LineShapes = ::testing::Types<Line2, Line3>;
TYPED_TEST_SUITE(CableKernel, LineShapes);

constexpr double kL = 2.5, kE = 7.0e4, kArea = 0.03;

// A cable of length ~kL, rotated by R; line3 with its middle node off-centre and off-line
// (curved reference) when `curved`.
template <class Shape>
Eigen::Matrix<double, 3, Shape::kNodes> reference_cable(const Mat3& R, bool curved) {
  Eigen::Matrix<double, 3, Shape::kNodes> X;
  X.col(0) = Vec3(0, 0, 0);
  X.col(1) = Vec3(kL, 0, 0);
  if constexpr (Shape::kNodes == 3)
    X.col(2) = curved ? Vec3(0.45 * kL, 0.12 * kL, 0.05 * kL) : Vec3(0.4 * kL, 0, 0);
  return R * X;
}

TYPED_TEST(CableKernel, A4TangentMatchesFiniteDifferences) {
  using S = TypeParam;
  using C = Cable<S>;
  test::Random rnd(700 + S::kNodes);
  struct Case {
    const char* label;
    double stretch;
    bool compression;
  };
  for (const Case& cs : {Case{"taut", 1.15, false}, Case{"truss in compression", 0.85, true},
                         Case{"truss in tension", 1.1, true}}) {
    double worst_K = 0, worst_U = 0;
    for (int trial = 0; trial < 4; ++trial) {
      const Mat3 R = rnd.rotation(rnd.uniform(0, 3));
      const typename C::Nodes X = reference_cable<S>(R, trial % 2 == 1);
      typename C::Points pts;
      ASSERT_GT(C::setup(X, kE, kArea, pts), 0);
      const CableLaw law{kE, cs.compression};
      const Mat3 Q = rnd.rotation(rnd.uniform(0, 3));
      typename C::Nodes x;
      for (int n = 0; n < S::kNodes; ++n)
        x.col(n) = cs.stretch * Q * X.col(n) + 0.01 * kL * rnd.vec3(-1, 1);
      typename C::Vector r, r2;
      typename C::Matrix K;
      C::force_tangent(pts, law, x, r, K);
      C::force(pts, law, x, r2);
      EXPECT_LT(test::rel_max_error(r2, r), 1e-14);
      const double h = 1e-6 * kL;
      const auto Kfd = test::fd_jacobian<typename C::Vector, typename C::Matrix>(
          x, h,
          [&](const typename C::Nodes& y, typename C::Vector& f) { C::force(pts, law, y, f); });
      const double eK = test::rel_max_error(K, Kfd);
      EXPECT_LT(eK, 1e-6) << S::kName << " " << cs.label;
      const auto rfd = test::fd_gradient<typename C::Vector>(
          x, h, [&](const typename C::Nodes& y) { return C::strain_energy(pts, law, y); });
      const double eU = test::rel_max_error(rfd, r);
      EXPECT_LT(eU, 1e-6) << S::kName << " " << cs.label;
      worst_K = std::max(worst_K, eK);
      worst_U = std::max(worst_U, eU);
    }
    std::cout << "A4 worst relative error " << S::kName << " " << cs.label << ": tangent "
              << worst_K << ", energy gradient " << worst_U << "\n";
  }
}

TYPED_TEST(CableKernel, SlackCableCarriesNothing) {
  using S = TypeParam;
  using C = Cable<S>;
  test::Random rnd(800 + S::kNodes);
  const typename C::Nodes X = reference_cable<S>(rnd.rotation(1.0), true);
  typename C::Points pts;
  C::setup(X, kE, kArea, pts);
  typename C::Nodes x = 0.8 * X;
  for (int n = 0; n < S::kNodes; ++n) x.col(n) += 0.01 * kL * rnd.vec3(-1, 1);
  typename C::Vector r;
  typename C::Matrix K;
  C::force_tangent(pts, CableLaw{kE, false}, x, r, K);
  EXPECT_EQ(r.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(K.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(C::strain_energy(pts, CableLaw{kE, false}, x), 0.0);
  // The same state as a truss is compressed: nonzero, pulling the nodes apart.
  C::force(pts, CableLaw{kE, true}, x, r);
  EXPECT_GT(r.cwiseAbs().maxCoeff(), 0.0);
}

TYPED_TEST(CableKernel, A5RigidMotionGivesNoForce) {
  using S = TypeParam;
  using C = Cable<S>;
  test::Random rnd(900 + S::kNodes);
  const typename C::Nodes X = reference_cable<S>(rnd.rotation(0.3), true);
  typename C::Points pts;
  C::setup(X, kE, kArea, pts);
  const CableLaw law{kE, true};
  double worst = 0;
  for (const double angle : {0.7, 2.0, 3.1}) {
    const Mat3 R = rnd.rotation(angle);
    const typename C::Nodes x = (R * X).colwise() + kL * rnd.vec3(-1, 1);
    typename C::Vector r;
    C::force(pts, law, x, r);
    worst = std::max(worst, r.cwiseAbs().maxCoeff() / (kE * kArea));
  }
  EXPECT_LT(worst, 1e-12);
  std::cout << "A5 " << S::kName << ": rigid-motion force / (E A) " << worst << "\n";
}

TYPED_TEST(CableKernel, A7MassAndTrueForce) {
  using S = TypeParam;
  using C = Cable<S>;
  test::Random rnd(1000 + S::kNodes);
  const Mat3 R = rnd.rotation(2.2);
  // Straight cable (line3: middle node at 0.4 L, a non-uniform map; |X'| stays linear in ξ).
  const typename C::Nodes X = reference_cable<S>(R, false);
  typename C::Points pts;
  C::setup(X, kE, kArea, pts);
  const double rho = 7800;
  EXPECT_NEAR(C::length(pts), kL, 1e-14 * kL);
  const typename C::NodeMatrix M = rho * kArea * C::mass(pts);
  const double err = std::abs(M.sum() - rho * kArea * kL) / (rho * kArea * kL);
  EXPECT_LT(err, 1e-14);
  const Eigen::VectorXd lumped = M.rowwise().sum();
  EXPECT_GT(lumped.minCoeff(), 0);
  EXPECT_NEAR(lumped.sum(), rho * kArea * kL, 1e-13 * rho * kArea * kL);
  std::cout << "A7 " << S::kName << ": consistent mass / (rho A L) - 1 = " << err
            << ", lumped (row sum) min/mean " << lumped.minCoeff() / (lumped.sum() / S::kNodes)
            << "\n";
  // Uniform stretch λ: true force E A ε λ with ε = (λ² − 1)/2.
  const double lam = 1.07, eps = 0.5 * (lam * lam - 1);
  const typename C::Nodes x = rnd.rotation(1.1) * (lam * X);
  EXPECT_NEAR(C::true_force(pts, CableLaw{kE, false}, x), kE * kArea * eps * lam,
              1e-12 * kE * kArea * eps * lam);
  // End forces of a straight stretched cable: ±(2nd PK force N) times the current direction
  // scaled by λ, i.e. the true force along the cable; interior nodes carry nothing.
  typename C::Vector r;
  C::force(pts, CableLaw{kE, false}, x, r);
  const Vec3 dir = (x.col(1) - x.col(0)).normalized();
  EXPECT_LT((r.template segment<3>(3) - kE * kArea * eps * lam * dir).norm(),
            1e-12 * kE * kArea * eps * lam);
  EXPECT_LT((r.template segment<3>(0) + kE * kArea * eps * lam * dir).norm(),
            1e-12 * kE * kArea * eps * lam);
  if constexpr (S::kNodes == 3) {
    EXPECT_LT(r.template segment<3>(6).norm(), 1e-12 * kE * kArea * eps * lam);
  }
}

}  // namespace
}  // namespace velum

namespace velum {
namespace {

TYPED_TEST(CableKernel, TensionStiffnessIsTheTangentsAcrossAStretchedCable) {
  // A straight cable stretched by λ along itself carries S = E (λ² − 1) / 2; across it the
  // tangent is its geometric stiffness alone: area · S times the tension stiffness, which for
  // a 2-node cable of length L is [1 −1; −1 1] / L.
  using S = TypeParam;
  using C = Cable<S>;
  test::Random rnd(720 + S::kNodes);
  const double lambda = 1.03;
  const Mat3 R = rnd.rotation(0.9);
  const typename C::Nodes X = reference_cable<S>(R, false);
  typename C::Points pts;
  ASSERT_GT(C::setup(X, kE, kArea, pts), 0);
  typename C::Vector r;
  typename C::Matrix K;
  C::force_tangent(pts, CableLaw{kE, false}, lambda * X, r, K);
  const Vec3 across = R * Vec3(0, 0.6, 0.8);
  typename C::NodeMatrix transverse;
  for (int m = 0; m < S::kNodes; ++m)
    for (int n = 0; n < S::kNodes; ++n)
      transverse(m, n) = across.dot(K.template block<3, 3>(3 * m, 3 * n) * across);
  const typename C::NodeMatrix Kt = C::tension_stiffness(pts);
  const double stress = kE * (lambda * lambda - 1) / 2;
  EXPECT_LT(test::rel_max_error(transverse, (kArea * stress) * Kt), 1e-12) << S::kName;
  if constexpr (S::kNodes == 2) {
    typename C::NodeMatrix line;
    line << 1, -1, -1, 1;
    EXPECT_LT(test::rel_max_error(Kt, line / kL), 1e-14);
  }
}

}  // namespace
}  // namespace velum
