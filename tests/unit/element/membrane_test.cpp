// Membrane kernels, VERIFICATION A4 (consistent tangent, energy gradient and follower-pressure
// load stiffness against central finite differences), A5 (objectivity under large rigid
// rotations) and A7 (consistent and lumped mass), for every surface shape and law; the
// geometric stiffness of a uniform unit tension.
#include <gtest/gtest.h>

#include <iostream>

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
class MembraneKernel : public ::testing::Test {};
using SurfaceShapes = ::testing::Types<Tri3, Tri6, Quad4, Quad8, Quad9>;
TYPED_TEST_SUITE(MembraneKernel, SurfaceShapes);

constexpr double kH = 1.3;    // element size
constexpr double kT0 = 0.02;  // thickness

// ---------------------------------------------------------------------------------------- A4

// A flat element in the plane z = 0 with straight edges: corners perturbed, mid-side nodes at
// edge midpoints (the quad9's centre node at the corners' mean), so its area is the polygon's.
template <class S>
typename Membrane<S>::Nodes straight_flat_element(test::Random& rnd, double& area) {
  typename Membrane<S>::Nodes X =
      test::distorted_element<S>(rnd, kH, 0.1, 0.0, Mat3::Identity(), Vec3::Zero());
  const int corners = (S::kNodes == 3 || S::kNodes == 6) ? 3 : 4;
  for (int k = corners; k < S::kNodes; ++k) {
    if (k - corners < corners) {
      const int a = k - corners, b = (a + 1) % corners;
      X.col(k) = 0.5 * (X.col(a) + X.col(b));
    }
  }
  area = 0;
  for (int a = 0; a < corners; ++a) {
    const int b = (a + 1) % corners;
    area += 0.5 * (X(0, a) * X(1, b) - X(0, b) * X(1, a));
  }
  if (S::kNodes == 9) X.col(8) = 0.25 * (X.col(0) + X.col(1) + X.col(2) + X.col(3));
  return X;
}

TYPED_TEST(MembraneKernel, A4TangentMatchesFiniteDifferences) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(100 + S::kNodes);
  for (const auto& [label, law] : test::test_laws()) {
    double worst_K = 0, worst_U = 0;
    for (int trial = 0; trial < 4; ++trial) {
      const Mat3 R = rnd.rotation(rnd.uniform(0, 3));
      const typename M::Nodes X =
          test::distorted_element<S>(rnd, kH, 0.08, 0.15 * (trial % 2), R, rnd.vec3(-2, 2));
      typename M::Points pts;
      ASSERT_GT(M::setup(X, law.Q(), test::axes_at(30 + 10 * trial, R), kT0, pts), 0);
      // Random deformed state: stretch, shear, rotation and node noise (some points may be in
      // compression; the law is linear in E so the tangent must hold everywhere).
      Mat3 F = Mat3::Identity() + 0.2 * rnd.mat3(-1, 1);
      const Vec3 c = rnd.vec3(-1, 1);
      typename M::Nodes x;
      for (int n = 0; n < S::kNodes; ++n) x.col(n) = F * X.col(n) + c + 0.08 * kH * rnd.vec3(-1, 1);
      typename M::Vector r, r2;
      typename M::Matrix K;
      M::force_tangent(pts, x, r, K);
      M::force(pts, x, r2);
      EXPECT_LT(test::rel_max_error(r2, r), 1e-13) << label;
      const double h = 1e-6 * kH;
      const auto Kfd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
          x, h, [&](const typename M::Nodes& y, typename M::Vector& f) { M::force(pts, y, f); });
      const double eK = test::rel_max_error(K, Kfd);
      EXPECT_LT(eK, 1e-6) << S::kName << " " << label;
      EXPECT_LT((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-12 * K.cwiseAbs().maxCoeff());
      const auto rfd = test::fd_gradient<typename M::Vector>(
          x, h, [&](const typename M::Nodes& y) { return M::strain_energy(pts, y); });
      const double eU = test::rel_max_error(rfd, r);
      EXPECT_LT(eU, 1e-6) << S::kName << " " << label;
      worst_K = std::max(worst_K, eK);
      worst_U = std::max(worst_U, eU);
    }
    std::cout << "A4 worst relative error " << S::kName << " " << label << ": tangent " << worst_K
              << ", energy gradient " << worst_U << "\n";
  }
}

TYPED_TEST(MembraneKernel, A4TangentOfPrestressedAndWrinklingSheetsMatchesFiniteDifferences) {
  // The laws evaluated at each point (LawPoints) and the prestressed fast path, on every law;
  // the deformed states are chosen so that some points are taut, some wrinkled, some slack.
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(150 + S::kNodes);
  int states[3] = {0, 0, 0};
  for (const auto& [label, elastic] : test::test_laws()) {
    // A fibre sheet that wrinkles takes no sheet prestress (its families go slack one by one).
    const Vec3 S0 = label == "fibers" ? Vec3::Zero() : Vec3(30.0, 12.0, -3.0);
    // κ = 0: the tension field itself, whose tangent is its derivative; the default residual
    // stiffness adds κ Q to the tangent only (checked below to leave the forces alone).
    const SheetLaw wrinkling = SheetLaw(elastic).with_prestress(S0).with_wrinkling(0.0);
    const SheetLaw regularised = SheetLaw(elastic).with_prestress(S0).with_wrinkling();
    const LawPoints law{&wrinkling};
    const LawPoints law_kappa{&regularised};
    const PrestressedPoints prestressed{S0};
    for (int trial = 0; trial < 4; ++trial) {
      const Mat3 R = rnd.rotation(rnd.uniform(0, 3));
      const typename M::Nodes X =
          test::distorted_element<S>(rnd, kH, 0.08, 0.15 * (trial % 2), R, rnd.vec3(-2, 2));
      typename M::Points pts;
      ASSERT_GT(M::setup(X, elastic.Q(), test::axes_at(30 + 10 * trial, R), kT0, pts), 0);
      Mat3 F = Mat3::Identity() + 0.12 * rnd.mat3(-1, 1);
      typename M::Nodes x;
      for (int n = 0; n < S::kNodes; ++n) x.col(n) = F * X.col(n) + 0.04 * kH * rnd.vec3(-1, 1);
      for (int q = 0; q < S::kPoints; ++q) {
        const Eigen::Matrix<double, 3, 2> g = x * pts.shapes->dN[q];
        ++states[static_cast<int>(law.evaluate(pts[q], M::strain(pts[q], g)).state)];
      }
      const double h = 1e-6 * kH;
      auto check = [&](const auto& policy, const char* what) {
        typename M::Vector r, r2;
        typename M::Matrix K;
        M::force_tangent(pts, policy, x, r, K);
        M::force(pts, policy, x, r2);
        if (r.cwiseAbs().maxCoeff() == 0) return;  // every point slack: no force, no stiffness
        EXPECT_LT(test::rel_max_error(r2, r), 1e-13) << label << " " << what;
        const auto Kfd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
            x, h, [&](const typename M::Nodes& y, typename M::Vector& f) {
              M::force(pts, policy, y, f);
            });
        EXPECT_LT(test::rel_max_error(K, Kfd), 1e-6) << S::kName << " " << label << " " << what;
        const auto rfd = test::fd_gradient<typename M::Vector>(
            x, h, [&](const typename M::Nodes& y) { return M::strain_energy(pts, policy, y); });
        EXPECT_LT(test::rel_max_error(rfd, r), 1e-6) << S::kName << " " << label << " " << what;
      };
      check(law, "wrinkling");
      {
        typename M::Vector r, rk;
        M::force(pts, law, x, r);
        M::force(pts, law_kappa, x, rk);
        EXPECT_EQ(r, rk) << label << ": the residual stiffness changed the forces";
      }
      check(prestressed, "prestressed");
    }
  }
  EXPECT_GT(states[0], 0);
  EXPECT_GT(states[1], 0);
  std::cout << S::kName << " points taut / wrinkled / slack: " << states[0] << " / " << states[1]
            << " / " << states[2] << "\n";
}

// An anisotropic sheet (Lekhnitskii coefficients non-zero) with a prestress.
SheetLaw anisotropic_prestressed_law() {
  AnisotropicConstants c;
  c.E1 = 2000.0, c.E2 = 1000.0, c.nu12 = 0.3, c.G12 = 400.0, c.eta1 = 0.25, c.eta2 = -0.15;
  return SheetLaw(PlaneStressLaw::anisotropic("a", c)).with_prestress({5, 7, 2});
}

// A distorted element turned by a random rotation of angle `turn`, set up in `pts` with its
// axes at `degrees`; returns its nodes moved by up to a tenth of its size.
template <class S>
typename Membrane<S>::Nodes deformed_element(test::Random& rnd, const SheetLaw& law, double turn,
                                             double degrees, typename Membrane<S>::Points& pts) {
  const Mat3 R = rnd.rotation(turn);
  const auto X = test::distorted_element<S>(rnd, kH, 0.08, 0.1, R, Vec3::Zero());
  Membrane<S>::setup(X, law.Q(), test::axes_at(degrees, R), kT0, pts);
  typename Membrane<S>::Nodes x = X;
  for (int n = 0; n < S::kNodes; ++n) x.col(n) += 0.1 * kH * rnd.vec3(-1, 1);
  return x;
}

TYPED_TEST(MembraneKernel, PrestressedAndGeneralLawPathsAgree) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(170 + S::kNodes);
  const SheetLaw law = anisotropic_prestressed_law();
  typename M::Points pts;
  const typename M::Nodes x = deformed_element<S>(rnd, law, 1.1, 35, pts);
  typename M::Vector r1, r2;
  typename M::Matrix K1, K2;
  M::force_tangent(pts, PrestressedPoints{law.prestress()}, x, r1, K1);
  M::force_tangent(pts, LawPoints{&law}, x, r2, K2);
  EXPECT_LT(test::rel_max_error(r1, r2), 1e-12);
  EXPECT_LT(test::rel_max_error(K1, K2), 1e-12);
  for (int q = 0; q < S::kPoints; ++q) {
    const Mat3 A = sheet_strain_map(pts[q].T);
    EXPECT_LT((A.transpose() * law.Q() * A * pts[q].t0dA - pts[q].D).cwiseAbs().maxCoeff(),
              1e-12 * pts[q].D.cwiseAbs().maxCoeff());
  }
}

TYPED_TEST(MembraneKernel, A4PressureLoadStiffnessMatchesFiniteDifferences) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(200 + S::kNodes);
  const auto law = PlaneStressLaw::isotropic("iso", 1000, 0.3);
  double worst = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const Mat3 R = rnd.rotation(rnd.uniform(0, 3));
    const typename M::Nodes X = test::distorted_element<S>(rnd, kH, 0.08, 0.1, R, Vec3::Zero());
    typename M::Points pts;
    M::setup(X, law.Q(), test::axes_at(0, R), kT0, pts);
    typename M::Nodes x = X;
    for (int n = 0; n < S::kNodes; ++n) x.col(n) += 0.15 * kH * rnd.vec3(-1, 1);
    const double p = rnd.uniform(0.5, 3);
    typename M::Vector f, f2;
    typename M::Matrix K;
    M::pressure_force_tangent(pts, x, p, f, K);
    M::pressure_force(pts, x, p, f2);
    EXPECT_LT(test::rel_max_error(f2, f), 1e-14);
    const auto Kfd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
        x, 1e-6 * kH, [&](const typename M::Nodes& y, typename M::Vector& g) {
          M::pressure_force(pts, y, p, g);
        });
    const double e = test::rel_max_error(K, Kfd);
    EXPECT_LT(e, 1e-6) << S::kName;
    worst = std::max(worst, e);
    // The total pressure force is p times the vector area of the current surface; for a flat
    // current configuration that is p A n.
  }
  std::cout << "A4 worst relative error " << S::kName << " pressure load stiffness: " << worst
            << "\n";
}

// The fused residual pass gives the two kernels' forces (bit for bit with GCC 12), every law.
TYPED_TEST(MembraneKernel, ForceAndPressureInOnePassAreTheTwoKernelsForces) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(230 + S::kNodes);
  const SheetLaw law = anisotropic_prestressed_law();
  typename M::Points pts;
  const typename M::Nodes x = deformed_element<S>(rnd, law, 0.7, 20, pts);
  const double p = 2.5;
  typename M::Vector r, f, r_fused, f_fused;
  auto same = [&](const auto& policy) {
    M::force(pts, policy, x, r);
    M::pressure_force(pts, x, p, f);
    M::force_and_pressure(pts, policy, x, p, r_fused, f_fused);
    EXPECT_TRUE(r_fused == r) << S::kName << ": " << test::rel_max_error(r_fused, r);
    EXPECT_TRUE(f_fused == f) << S::kName << ": " << test::rel_max_error(f_fused, f);
    EXPECT_GT(r.norm(), 0);
    EXPECT_GT(f.norm(), 0);
  };
  same(ElasticPoints{});
  same(PrestressedPoints{law.prestress()});
  same(LawPoints{&law});
}

TYPED_TEST(MembraneKernel, PressureResultantOnFlatElementIsPressureTimesArea) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(300 + S::kNodes);
  const Mat3 R = rnd.rotation(1.0);
  double area = 0;
  const typename M::Nodes X = straight_flat_element<S>(rnd, area);
  const typename M::Nodes Xr = R * X;
  typename M::Points pts;
  M::setup(Xr, PlaneStressLaw::isotropic("iso", 1, 0).Q(), test::axes_at(0, R), 1.0, pts);
  typename M::Vector f;
  M::pressure_force(pts, Xr, 2.5, f);
  Vec3 total = Vec3::Zero();
  for (int n = 0; n < S::kNodes; ++n) total += f.template segment<3>(3 * n);
  EXPECT_LT((total - 2.5 * area * R.col(2)).norm(), 1e-13 * 2.5 * area);
}

// A pressure along a fixed direction (snow per plan area, or per current area): its load
// stiffness against central differences, on curved, distorted elements tilted to the
// direction, and for both measures.
TYPED_TEST(MembraneKernel, A4DirectedPressureLoadStiffnessMatchesFiniteDifferences) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(400 + S::kNodes);
  const auto law = PlaneStressLaw::isotropic("iso", 1000, 0.3);
  double worst = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const bool projected = trial % 2 == 0;
    const Mat3 R = rnd.rotation(rnd.uniform(0, 1.2));
    const typename M::Nodes X = test::distorted_element<S>(rnd, kH, 0.08, 0.1, R, Vec3::Zero());
    typename M::Points pts;
    M::setup(X, law.Q(), test::axes_at(0, R), kT0, pts);
    typename M::Nodes x = X;
    for (int n = 0; n < S::kNodes; ++n) x.col(n) += 0.1 * kH * rnd.vec3(-1, 1);
    const Vec3 d = Vec3(0.2, -0.1, -1).normalized();
    const double p = rnd.uniform(0.5, 3);
    typename M::Vector f, f2;
    typename M::Matrix K;
    M::directed_pressure_force_tangent(pts, x, p, d, projected, f, K);
    M::directed_pressure_force(pts, x, p, d, projected, f2);
    EXPECT_LT(test::rel_max_error(f2, f), 1e-14);
    const auto Kfd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
        x, 1e-6 * kH, [&](const typename M::Nodes& y, typename M::Vector& g) {
          M::directed_pressure_force(pts, y, p, d, projected, g);
        });
    const double e = test::rel_max_error(K, Kfd);
    EXPECT_LT(e, 1e-6) << S::kName << (projected ? " projected" : " area");
    worst = std::max(worst, e);
  }
  std::cout << "A4 worst relative error " << S::kName
            << " directed pressure load stiffness: " << worst << "\n";
}

// Snow on a flat element tilted by 35° about x: per plan area the resultant is p times the
// plan area (A cos 35°), per current area p A, both along the load's direction whatever the
// side the normal faces.
TYPED_TEST(MembraneKernel, DirectedPressureResultantIsPressureTimesProjectedArea) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(500 + S::kNodes);
  double area = 0;
  const typename M::Nodes X = straight_flat_element<S>(rnd, area);
  const double angle = 35.0 * std::acos(-1.0) / 180.0;
  const Mat3 R = Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix();
  const Vec3 d(0, 0, -1);
  for (const double flip : {1.0, -1.0}) {  // normal up, then (mirrored element) down
    typename M::Nodes Xr = R * X;
    if (flip < 0) Xr.row(2) *= -1, Xr.row(1) *= -1;
    typename M::Points pts;
    M::setup(Xr, PlaneStressLaw::isotropic("iso", 1, 0).Q(), test::axes_at(0, R), 1.0, pts);
    for (const bool projected : {true, false}) {
      typename M::Vector f;
      M::directed_pressure_force(pts, Xr, 2.5, d, projected, f);
      Vec3 total = Vec3::Zero();
      for (int n = 0; n < S::kNodes; ++n) total += f.template segment<3>(3 * n);
      const double expected = 2.5 * area * (projected ? std::cos(angle) : 1.0);
      EXPECT_LT((total - expected * d).norm(), 1e-13 * expected) << S::kName;
    }
  }
}

// ---------------------------------------------------------------------------------------- A5

TYPED_TEST(MembraneKernel, A5ObjectivityUnderLargeRigidRotations) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(400 + S::kNodes);
  const auto laws = test::test_laws();
  const PlaneStressLaw& law = laws[2].second;  // anisotropic, eta != 0
  ASSERT_NE(law.Q()(0, 2), 0.0);
  const Mat3 R0 = rnd.rotation(0.6);
  const typename M::Nodes X = test::distorted_element<S>(rnd, kH, 0.08, 0.1, R0, Vec3::Zero());
  typename M::Points pts;
  M::setup(X, law.Q(), test::axes_at(30, R0), kT0, pts);
  // Pre-strain: a general homogeneous deformation plus node noise.
  const Mat3 F = Mat3::Identity() + 0.1 * rnd.mat3(-1, 1);
  typename M::Nodes x0;
  for (int n = 0; n < S::kNodes; ++n) x0.col(n) = F * X.col(n) + 0.03 * kH * rnd.vec3(-1, 1);
  std::array<Vec3, S::kPoints> S0;
  Vec3 e;
  Eigen::Matrix<double, 3, 2> g;
  double Smax = 0;
  for (int q = 0; q < S::kPoints; ++q) {
    M::strain_stress(pts, q, x0, e, S0[q], g);
    Smax = std::max(Smax, S0[q].cwiseAbs().maxCoeff());
  }
  typename M::Vector r0, r1;
  M::force(pts, x0, r0);
  double worst_S = 0, worst_r = 0, worst_rigid = 0;
  for (const double angle : {0.5, 1.7, 2.9, 3.1}) {
    const Mat3 R = rnd.rotation(angle);
    const Vec3 c = kH * rnd.vec3(-1, 1);
    typename M::Nodes x1 = (R * x0).colwise() + c;
    Vec3 S1;
    for (int q = 0; q < S::kPoints; ++q) {
      M::strain_stress(pts, q, x1, e, S1, g);
      worst_S = std::max(worst_S, (S1 - S0[q]).cwiseAbs().maxCoeff() / Smax);
    }
    M::force(pts, x1, r1);
    typename M::Vector Rr0;
    for (int n = 0; n < S::kNodes; ++n)
      Rr0.template segment<3>(3 * n) = R * r0.template segment<3>(3 * n);
    worst_r = std::max(worst_r, test::rel_max_error(r1, Rr0));
    // Rigid motion of the unstrained sheet: no force, relative to E t0 h.
    const typename M::Nodes xr = (R * X).colwise() + c;
    typename M::Vector rr;
    M::force(pts, xr, rr);
    worst_rigid = std::max(worst_rigid,
                           rr.cwiseAbs().maxCoeff() / (law.Q().cwiseAbs().maxCoeff() * kT0 * kH));
  }
  EXPECT_LT(worst_S, 1e-12);
  EXPECT_LT(worst_r, 1e-12);
  EXPECT_LT(worst_rigid, 1e-12);
  std::cout << "A5 " << S::kName << " anisotropic (axes 30 deg): worst relative change of S "
            << worst_S << ", of rotated force " << worst_r << ", rigid-motion force / (E t h) "
            << worst_rigid << "\n";
}

// ---------------------------------------------------------------------------------------- A7

// Lumped masses: row sum, or HRZ (diagonal scaled to the total) when asked.
template <class NodeMatrix>
Eigen::VectorXd lump(const NodeMatrix& M, bool hrz) {
  if (!hrz) return M.rowwise().sum();
  return M.diagonal() * (M.sum() / M.diagonal().sum());
}

TYPED_TEST(MembraneKernel, A7ConsistentAndLumpedMass) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(500 + S::kNodes);
  const int corners = (S::kNodes == 3 || S::kNodes == 6) ? 3 : 4;
  const Mat3 R = rnd.rotation(2.0);
  // Curved edges: every node perturbed in the plane. The area is the corner polygon plus, for
  // each quadratic edge, the parabolic segment (2/3) L d, d the normal offset of the mid-side
  // node from the chord (positive outward). Interior nodes (quad9) do not change the area.
  typename M::Nodes X =
      test::distorted_element<S>(rnd, kH, 0.08, 0.0, Mat3::Identity(), Vec3::Zero());
  double area = 0;
  for (int a = 0; a < corners; ++a) {
    const int b = (a + 1) % corners;
    area += 0.5 * (X(0, a) * X(1, b) - X(0, b) * X(1, a));
    if (S::kNodes > corners) {
      const Vec3 chord = X.col(b) - X.col(a);
      const Vec3 outward(chord.y(), -chord.x(), 0);  // counter-clockwise element
      const Vec3 d = X.col(corners + a) - 0.5 * (X.col(a) + X.col(b));
      area += 2.0 / 3.0 * d.dot(outward);  // (2/3) L (d . n) with outward = L n
    }
  }
  const typename M::Nodes Xr = (R * X).colwise() + Vec3(1, -2, 3);
  typename M::Points pts;
  M::setup(Xr, PlaneStressLaw::isotropic("iso", 1, 0).Q(), test::axes_at(0, R), kT0, pts);
  const double rho = 7.5;
  const typename M::NodeMatrix Mc = rho * M::mass(pts);
  const double err = std::abs(Mc.sum() - rho * kT0 * area) / (rho * kT0 * area);
  EXPECT_LT(err, 1e-13);
  EXPECT_LT((Mc - Mc.transpose()).cwiseAbs().maxCoeff(), 1e-15 * Mc.cwiseAbs().maxCoeff());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mc).eigenvalues()(0), 0);
  const bool hrz = S::kNodes == 6 || S::kNodes == 8;
  const Eigen::VectorXd lumped = lump(Mc, hrz);
  EXPECT_GT(lumped.minCoeff(), 0) << S::kName;
  EXPECT_NEAR(lumped.sum(), rho * kT0 * area, 1e-13 * rho * kT0 * area);
  if (hrz) {
    // The reason for HRZ: the row sums of the corner nodes are not positive.
    EXPECT_LE(Mc.rowwise().sum().minCoeff(), 1e-12 * Mc.sum()) << S::kName;
  }
  std::cout << "A7 " << S::kName << ": consistent mass / (rho t A) - 1 = " << err << ", lumped ("
            << (hrz ? "HRZ" : "row sum") << ") min/mean "
            << lumped.minCoeff() / (lumped.sum() / S::kNodes) << "\n";
}

// An independent 6x6-point Gauss product rule over the reference element (degree 11 per
// direction; triangles through the collapsed map r = u, s = v (1 - u)): add(w, N, dN) at each
// point.
template <class S, class Add>
void product_rule(const Add& add) {
  const auto [gx, gw] = test::gauss_legendre(6);
  const bool tri = S::kNodes == 3 || S::kNodes == 6;
  typename S::Values N;
  typename S::Derivs dN;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      double r = gx[i], s = gx[j], w = gw[i] * gw[j];
      if (tri) {
        const double u = 0.5 * (r + 1), v = 0.5 * (s + 1);
        r = u, s = v * (1 - u), w *= 0.25 * (1 - u);
      }
      S::eval(r, s, N, dN);
      add(w, N, dN);
    }
}

TYPED_TEST(MembraneKernel, A7MassOfUndistortedElementIsExact) {
  // Affine element: the consistent mass against the independent product rule.
  using S = TypeParam;
  using M = Membrane<S>;
  Mat3 A = Mat3::Identity();
  A(0, 1) = 0.3, A(1, 1) = 0.8;
  typename M::Nodes X;
  const auto nodes = S::nodes();
  for (int n = 0; n < S::kNodes; ++n) X.col(n) = A * Vec3(nodes[n][0], nodes[n][1], 0);
  typename M::Points pts;
  M::setup(X, PlaneStressLaw::isotropic("iso", 1, 0).Q(), SheetAxes{}, 1.0, pts);
  const typename M::NodeMatrix Mc = M::mass(pts);
  typename M::NodeMatrix ref = M::NodeMatrix::Zero();
  const double detA = A.topLeftCorner<2, 2>().determinant();
  product_rule<S>(
      [&](double w, const auto& N, const auto&) { ref += w * detA * N * N.transpose(); });
  EXPECT_LT(test::rel_max_error(Mc, ref), 1e-13) << S::kName;
}

}  // namespace
}  // namespace velum

namespace velum {
namespace {

// ------------------------------------------------------------------------- tension stiffness

TYPED_TEST(MembraneKernel, TensionStiffnessOfAffineElementIsTheLaplacians) {
  // A uniform unit tension's geometric stiffness is t ∫ ∇N·∇N dA: on an affine element tilted
  // out of the xy plane, against the independent product rule in its plane.
  using S = TypeParam;
  using M = Membrane<S>;
  Mat3 A = Mat3::Identity();
  A(0, 1) = 0.3, A(1, 1) = 0.8;
  test::Random rnd(900 + S::kNodes);
  const Mat3 R = rnd.rotation(1.1);
  typename M::Nodes X;
  const auto nodes = S::nodes();
  for (int n = 0; n < S::kNodes; ++n) X.col(n) = R * A * Vec3(nodes[n][0], nodes[n][1], 0);
  typename M::Points pts;
  M::setup(X, PlaneStressLaw::isotropic("iso", 1, 0).Q(), SheetAxes{}, kT0, pts);
  const typename M::NodeMatrix Kt = M::tension_stiffness(pts);
  typename M::NodeMatrix ref = M::NodeMatrix::Zero();
  const Mat2 A2 = A.topLeftCorner<2, 2>();
  product_rule<S>([&](double w, const auto&, const auto& dN) {
    const Eigen::Matrix<double, S::kNodes, 2> grad = dN * A2.inverse();  // ∂N/∂(x, y)
    ref += (w * A2.determinant() * kT0) * grad * grad.transpose();
  });
  EXPECT_LT(test::rel_max_error(Kt, ref), 1e-13) << S::kName;
}

TYPED_TEST(MembraneKernel, TensionStiffnessIsTheTangentsUnderAUniformTension) {
  // A flat distorted element stretched by λ in its plane carries S = E (λ² − 1) / (2 (1 − ν))
  // in every direction; normal to the plane the tangent is its geometric stiffness alone,
  // which must be S times the tension stiffness.
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(910 + S::kNodes);
  const double E = 3e5, nu = 0.3, lambda = 1.04;
  for (int trial = 0; trial < 3; ++trial) {
    double area = 0;
    const typename M::Nodes X = straight_flat_element<S>(rnd, area);
    typename M::Points pts;
    ASSERT_GT(M::setup(X, PlaneStressLaw::isotropic("iso", E, nu).Q(), SheetAxes{}, kT0, pts), 0);
    typename M::Vector r;
    typename M::Matrix K;
    M::force_tangent(pts, X * lambda, r, K);
    typename M::NodeMatrix normal;
    for (int m = 0; m < S::kNodes; ++m)
      for (int n = 0; n < S::kNodes; ++n) normal(m, n) = K(3 * m + 2, 3 * n + 2);
    const double stress = E * (lambda * lambda - 1) / (2 * (1 - nu));
    const typename M::NodeMatrix expected = stress * M::tension_stiffness(pts);
    EXPECT_LT(test::rel_max_error(normal, expected), 1e-12) << S::kName;
  }
}

}  // namespace
}  // namespace velum
