// VERIFICATION A1 (material admissibility and closed-form Q), A2 (rotation of the stiffness,
// Jones' transformed stiffness and engineering constants) and A3 (fibre network tensor).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>

#include "../support.hpp"
#include "velum/material/plane_stress.hpp"

namespace velum {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

// ---------------------------------------------------------------------------------------- A1

TEST(MaterialA1, ClosedFormQInvertsComplianceForRandomAdmissibleSets) {
  test::Random rnd(11);
  double worst = 0;
  int accepted = 0;
  for (int trial = 0; accepted < 500 && trial < 20000; ++trial) {
    AnisotropicConstants c;
    c.E1 = std::pow(10.0, rnd.uniform(-1, 4));
    c.E2 = c.E1 * std::pow(10.0, rnd.uniform(-1, 1));
    c.nu12 = rnd.uniform(-0.5, 0.7);
    c.G12 = std::sqrt(c.E1 * c.E2) * rnd.uniform(0.05, 0.6);
    c.eta1 = rnd.uniform(-0.6, 0.6);
    c.eta2 = rnd.uniform(-0.6, 0.6);
    // Admissible means S positive definite; keep sets away from the boundary so that the
    // check measures the closed form, not the conditioning of a nearly singular S.
    const Mat3 S = compliance(c);
    const Eigen::Vector3d d = S.diagonal().cwiseSqrt().cwiseInverse();
    const Mat3 Sn = d.asDiagonal() * S * d.asDiagonal();
    if (Eigen::SelfAdjointEigenSolver<Mat3>(Sn).eigenvalues()(0) < 0.05) continue;
    const Mat3 Q = PlaneStressLaw::anisotropic("random", c).Q();
    EXPECT_LT((Q * S - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((Q - Q.transpose()).cwiseAbs().maxCoeff(), 1e-12 * Q.cwiseAbs().maxCoeff());
    worst = std::max(worst, (Q * S - Mat3::Identity()).cwiseAbs().maxCoeff());
    ++accepted;
  }
  EXPECT_EQ(accepted, 500);
  std::cout << "A1 worst |Q S - I| over " << accepted << " random admissible sets: " << worst
            << "\n";
  RecordProperty("A1_worst_QS_minus_I", std::to_string(worst));
}

TEST(MaterialA1, OrthotropicLimit) {
  const double E1 = 3000, E2 = 1200, nu12 = 0.28, G = 450, nu21 = nu12 * E2 / E1;
  const Mat3 Q = PlaneStressLaw::orthotropic("o", E1, E2, nu12, G, false).Q();
  Mat3 ref = Mat3::Zero();
  ref(0, 0) = E1 / (1 - nu12 * nu21);
  ref(1, 1) = E2 / (1 - nu12 * nu21);
  ref(0, 1) = ref(1, 0) = nu12 * E2 / (1 - nu12 * nu21);
  ref(2, 2) = G;
  EXPECT_LT(test::rel_max_error(Q, ref), 1e-14);
  EXPECT_EQ(Q(0, 2), 0.0);
  EXPECT_EQ(Q(1, 2), 0.0);
}

TEST(MaterialA1, IsotropicLimit) {
  for (const double nu : {-0.5, 0.0, 0.3, 0.49}) {
    const double E = 2.1e5;
    const Mat3 Q = PlaneStressLaw::isotropic("i", E, nu).Q();
    Mat3 ref;
    ref << 1, nu, 0, nu, 1, 0, 0, 0, (1 - nu) / 2;
    ref *= E / (1 - nu * nu);
    EXPECT_LT(test::rel_max_error(Q, ref), 1e-14) << "nu = " << nu;
    // Isotropy: Q is invariant under any in-plane rotation.
    const double th = 0.7;
    Mat2 T;
    T << std::cos(th), std::sin(th), -std::sin(th), std::cos(th);
    EXPECT_LT(test::rel_max_error(transform_stiffness(Q, T), ref), 1e-14);
  }
}

TEST(MaterialA1, FirtShearModulus) {
  const double E1 = 4000, E2 = 1000, nu12 = 0.4, nu21 = nu12 * E2 / E1;
  const double G = std::sqrt(E1 * E2) / (2 * (1 + std::sqrt(nu12 * nu21)));
  EXPECT_NEAR(firt_shear_modulus(E1, E2, nu12), G, 1e-12 * G);
  const Mat3 Q = PlaneStressLaw::orthotropic("firt", E1, E2, nu12, -1.0, true).Q();
  EXPECT_NEAR(Q(2, 2), G, 1e-12 * G);
  // Firt's G reduces to the isotropic E / (2 (1 + nu)).
  EXPECT_NEAR(firt_shear_modulus(1000, 1000, 0.3), 1000 / 2.6, 1e-12 * 1000);
}

// Every rejection names the material and the violated condition.
void expect_rejected(const std::function<PlaneStressLaw()>& make, const std::string& name,
                     const std::string& condition) {
  try {
    make();
    ADD_FAILURE() << "material '" << name << "' accepted; expected rejection: " << condition;
  } catch (const MaterialError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'" + name + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find(condition), std::string::npos) << msg;
  }
}

TEST(MaterialA1, NonAdmissibleSetsAreRejected) {
  using L = PlaneStressLaw;
  AnisotropicConstants ok;
  ok.E1 = 2000, ok.E2 = 1000, ok.nu12 = 0.3, ok.G12 = 400;
  auto with = [&](auto change) {
    AnisotropicConstants c = ok;
    change(c);
    return c;
  };
  expect_rejected([&] { return L::anisotropic("negE1", with([](auto& c) { c.E1 = -1; })); },
                  "negE1", "E1 must be positive");
  expect_rejected([&] { return L::anisotropic("zeroE2", with([](auto& c) { c.E2 = 0; })); },
                  "zeroE2", "E2 must be positive");
  expect_rejected([&] { return L::anisotropic("zeroG", with([](auto& c) { c.G12 = 0; })); },
                  "zeroG", "shear modulus G12 must be positive");
  expect_rejected([&] { return L::anisotropic("negG", with([](auto& c) { c.G12 = -5; })); }, "negG",
                  "shear modulus G12 must be positive");
  // nu12^2 > E1/E2: 1.5^2 = 2.25 > 2.
  expect_rejected([&] { return L::anisotropic("bignu", with([](auto& c) { c.nu12 = 1.5; })); },
                  "bignu", "must be below E1/E2");
  expect_rejected([&] { return L::orthotropic("bignu2", 1000, 4000, 0.6, 100, false); }, "bignu2",
                  "must be below E1/E2");
  // Large coupling coefficients: Delta <= 0.
  expect_rejected(
      [&] { return L::anisotropic("bigeta", with([](auto& c) { c.eta1 = 2.0, c.eta2 = 1.5; })); },
      "bigeta", "Delta");
  // Non-symmetric and indefinite matrices.
  Mat3 Qns;
  Qns << 10, 2, 0, 3, 10, 0, 0, 0, 4;
  expect_rejected([&] { return L::matrix("nonsym", Qns); }, "nonsym", "symmetric");
  Mat3 Qind;
  Qind << 10, 20, 0, 20, 10, 0, 0, 0, 4;
  expect_rejected([&] { return L::matrix("indef", Qind); }, "indef", "positive semi-definite");
  Mat3 Qneg = Mat3::Identity();
  Qneg(2, 2) = -1;
  expect_rejected([&] { return L::matrix("negdiag", Qneg); }, "negdiag", "positive semi-definite");
  // Fibres.
  expect_rejected([&] { return L::fibers("nofib", {}); }, "nofib", "at least one fibre family");
  expect_rejected(
      [&] {
        return L::fibers("negfib", {{100, 0}, {-5, 90}});
      },
      "negfib", "fibre modulus E must be positive");
  // Isotropic nu out of (-1, 1) and non-positive E.
  expect_rejected([&] { return L::isotropic("nu1", 100, 1.0); }, "nu1", "Poisson's ratio");
  expect_rejected([&] { return L::isotropic("nu-15", 100, -1.5); }, "nu-15", "Poisson's ratio");
  expect_rejected([&] { return L::isotropic("E0", 0, 0.3); }, "E0", "Young's modulus");
}

TEST(MaterialA1, SemiDefiniteMatrixIsAccepted) {
  // One fibre family along m1: Q = diag(E, 0, 0) is admissible (positive semi-definite).
  Mat3 Q = Mat3::Zero();
  Q(0, 0) = 100;
  EXPECT_NO_THROW(PlaneStressLaw::matrix("cable-like", Q));
  EXPECT_EQ(PlaneStressLaw::matrix("cable-like", Q).Q(), Q);
}

// ---------------------------------------------------------------------------------------- A2

// Jones, Mechanics of Composite Materials, Eq. 2.84: transformed reduced stiffness for
// principal axis 1 at angle theta from x.
Mat3 jones_qbar(const Mat3& Q, double th) {
  const double c = std::cos(th), s = std::sin(th);
  const double Q11 = Q(0, 0), Q12 = Q(0, 1), Q22 = Q(1, 1), Q66 = Q(2, 2);
  const double c2 = c * c, s2 = s * s;
  Mat3 B;
  B(0, 0) = Q11 * c2 * c2 + 2 * (Q12 + 2 * Q66) * s2 * c2 + Q22 * s2 * s2;
  B(0, 1) = (Q11 + Q22 - 4 * Q66) * s2 * c2 + Q12 * (s2 * s2 + c2 * c2);
  B(1, 1) = Q11 * s2 * s2 + 2 * (Q12 + 2 * Q66) * s2 * c2 + Q22 * c2 * c2;
  B(0, 2) = (Q11 - Q12 - 2 * Q66) * s * c2 * c + (Q12 - Q22 + 2 * Q66) * s2 * s * c;
  B(1, 2) = (Q11 - Q12 - 2 * Q66) * s2 * s * c + (Q12 - Q22 + 2 * Q66) * s * c2 * c;
  B(2, 2) = (Q11 + Q22 - 2 * Q12 - 2 * Q66) * s2 * c2 + Q66 * (s2 * s2 + c2 * c2);
  B(1, 0) = B(0, 1), B(2, 0) = B(0, 2), B(2, 1) = B(1, 2);
  return B;
}

// T(a, alpha) = m_a . e_alpha with m1 = (cos, sin), m2 = (-sin, cos).
Mat2 rotation_T(double th) {
  Mat2 T;
  T << std::cos(th), std::sin(th), -std::sin(th), std::cos(th);
  return T;
}

TEST(MaterialA2, RotatedStiffnessEqualsJonesQbar) {
  const Mat3 Q = PlaneStressLaw::orthotropic("jones", 2.0, 1.0, 0.3, 0.5, false).Q();
  double worst = 0;
  for (double deg = -180; deg <= 180; deg += 7.5) {
    const Mat3 out = transform_stiffness(Q, rotation_T(deg * kDeg));
    const double err = test::rel_max_error(out, jones_qbar(Q, deg * kDeg));
    EXPECT_LT(err, 1e-13) << deg << " deg";
    worst = std::max(worst, err);
  }
  std::cout << "A2 worst relative error of Q(theta) against Jones' Qbar: " << worst << "\n";
}

TEST(MaterialA2, RotationComposesAndInverts) {
  // An anisotropic Q: rotating by a then b equals rotating by a + b; by -a undoes a.
  const auto laws = test::test_laws();
  const Mat3 Q = laws[2].second.Q();
  const double a = 0.4, b = -1.3;
  const Mat3 ab = transform_stiffness(transform_stiffness(Q, rotation_T(a)), rotation_T(b));
  EXPECT_LT(test::rel_max_error(ab, transform_stiffness(Q, rotation_T(a + b))), 1e-14);
  const Mat3 back = transform_stiffness(transform_stiffness(Q, rotation_T(a)), rotation_T(-a));
  EXPECT_LT(test::rel_max_error(back, Q), 1e-14);
}

TEST(MaterialA2, EngineeringConstantsOffAxis) {
  const Mat3 Q = PlaneStressLaw::orthotropic("jones", 2.0, 1.0, 0.3, 0.5, false).Q();
  struct Case {
    double deg, Ex, nuxy;
  };
  double worst = 0;
  for (const Case& c : {Case{30, 1.509434, 0.283019}, Case{45, 1.25, 0.25}}) {
    const Mat3 Sx = transform_stiffness(Q, rotation_T(c.deg * kDeg)).inverse();
    const double Ex = 1 / Sx(0, 0), nuxy = -Sx(0, 1) / Sx(0, 0);
    EXPECT_NEAR(Ex, c.Ex, 1e-6) << c.deg;
    EXPECT_NEAR(nuxy, c.nuxy, 1e-6) << c.deg;
    worst = std::max({worst, std::abs(Ex - c.Ex), std::abs(nuxy - c.nuxy)});
    std::cout << "A2 theta = " << c.deg << " deg: Ex = " << Ex << " (ref " << c.Ex
              << "), nuxy = " << nuxy << " (ref " << c.nuxy << ")\n";
  }
  std::cout << "A2 worst absolute error of Ex, nuxy (refs given to 6 decimals): " << worst << "\n";
}

// ---------------------------------------------------------------------------------------- A3

// Engineering Voigt matrix of sum_f E_f n n n n, built index by index (independent of the
// library's Voigt mapping): rows/cols (11, 22, 12), no factor 2 on shear rows or columns.
Mat3 fiber_voigt_reference(const std::vector<FiberFamily>& fams) {
  Mat3 Q = Mat3::Zero();
  for (const auto& f : fams) {
    const double c = std::cos(f.angle_deg * kDeg), s = std::sin(f.angle_deg * kDeg);
    Mat3 q;
    q << c * c * c * c, c * c * s * s, c * c * c * s,  //
        c * c * s * s, s * s * s * s, c * s * s * s,   //
        c * c * c * s, c * s * s * s, c * c * s * s;
    Q += f.E * q;
  }
  return Q;
}

TEST(MaterialA3, BraidedFamiliesAt75And105) {
  const Mat3 Q = PlaneStressLaw::fibers("braid", {{100, 75}, {100, 105}}).Q();
  // Hand values: c = cos 75 deg = 0.258819..., s = sin 75 deg = 0.965926...; the two
  // families cancel the odd terms (c changes sign), so Q16 = Q26 = 0.
  const double c = 0.25881904510252074, s = 0.96592582628906831;
  const double Q11 = 2 * 100 * std::pow(c, 4), Q22 = 2 * 100 * std::pow(s, 4);
  const double Q12 = 2 * 100 * c * c * s * s;
  EXPECT_NEAR(Q(0, 0), Q11, 1e-12);  // 0.897459...
  EXPECT_NEAR(Q(1, 1), Q22, 1e-12);  // 174.1026...
  EXPECT_NEAR(Q(0, 1), Q12, 1e-12);  // 12.5
  EXPECT_NEAR(Q(1, 0), Q12, 1e-12);
  EXPECT_NEAR(Q(2, 2), Q12, 1e-12);  // engineering Voigt: cos^2 sin^2, not 2 cos^2 sin^2
  EXPECT_NEAR(Q(0, 2), 0.0, 1e-12);
  EXPECT_NEAR(Q(1, 2), 0.0, 1e-12);
  EXPECT_NEAR(Q12, 12.5, 1e-12);  // 2·100·(sin 150°/2)^2
  const double err = (Q - fiber_voigt_reference({{100, 75}, {100, 105}})).cwiseAbs().maxCoeff();
  std::cout << "A3 Q(75/105 deg, E = 100) = [" << Q.row(0) << "; " << Q.row(1) << "; " << Q.row(2)
            << "], worst abs error " << err << "\n";
  // The stress of a fibre strain: each family carries E (n.E.n) along itself.
  const Vec3 eps(0.01, -0.004, 0.006);  // [E11, E22, 2 E12]
  Vec3 ref = Vec3::Zero();
  for (double deg : {75.0, 105.0}) {
    const Vec2 n(std::cos(deg * kDeg), std::sin(deg * kDeg));
    Mat2 E;
    E << eps[0], eps[2] / 2, eps[2] / 2, eps[1];
    const Mat2 S = 100 * n.dot(E * n) * n * n.transpose();
    ref += Vec3(S(0, 0), S(1, 1), S(0, 1));
  }
  EXPECT_LT(test::rel_max_error(Q * eps, ref), 1e-13);
}

TEST(MaterialA3, SingleFamilyOffAxisHasNoFactorTwo) {
  const double th = 30 * kDeg, c = std::cos(th), s = std::sin(th);
  const Mat3 Q = PlaneStressLaw::fibers("one", {{10, 30}}).Q();
  EXPECT_NEAR(Q(0, 2), 10 * c * c * c * s, 1e-13);
  EXPECT_NEAR(Q(1, 2), 10 * c * s * s * s, 1e-13);
  EXPECT_NEAR(Q(2, 2), 10 * c * c * s * s, 1e-13);
}

TEST(MaterialA3, RandomFamiliesMatchTensorAndRotate) {
  test::Random rnd(3);
  double worst = 0;
  for (int k = 0; k < 50; ++k) {
    std::vector<FiberFamily> fams;
    const int nf = 1 + k % 4;
    for (int f = 0; f < nf; ++f) fams.push_back({rnd.uniform(1, 500), rnd.uniform(-180, 180)});
    const Mat3 Q = PlaneStressLaw::fibers("rand", fams).Q();
    const double err = test::rel_max_error(Q, fiber_voigt_reference(fams));
    EXPECT_LT(err, 1e-13);
    worst = std::max(worst, err);
    // Rotating the sheet axes by a (m1 at angle a from x) moves every fibre to angle + a.
    const double a = rnd.uniform(-3, 3);
    std::vector<FiberFamily> shifted = fams;
    for (auto& f : shifted) f.angle_deg += a / kDeg;
    EXPECT_LT(test::rel_max_error(transform_stiffness(Q, rotation_T(a)),
                                  PlaneStressLaw::fibers("s", shifted).Q()),
              1e-12);
  }
  std::cout << "A3 worst relative error of fibre Q against sum E n n n n: " << worst << "\n";
}

}  // namespace
}  // namespace velum
