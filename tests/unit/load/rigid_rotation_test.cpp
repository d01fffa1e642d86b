// The free rigid body's rotation (src/load/rigid_rotation.hpp) without moments: an asymmetric
// body spun about its intermediate axis flips (Dzhanibekov) while its angular momentum is kept
// exactly and its energy within a bound that falls as the step squared.
#include <gtest/gtest.h>

#include <iostream>

#include "load/rigid_rotation.hpp"

namespace velum {
namespace {

struct SpinRun {
  double momentum_error = 0, energy_error = 0;
  int flips = 0;
};

SpinRun spin(double h, double T) {
  // Principal moments 1, 2, 3 along axes turned away from the global ones.
  const Mat3 Q = rigid::rotation_matrix(Vec3(0.3, -0.2, 0.5));
  const Mat3 J0 = Q * Vec3(1.0, 2.0, 3.0).asDiagonal() * Q.transpose();
  const Vec3 axis = Q.col(1);  // the intermediate axis, slightly perturbed
  rigid::Rotation r(J0, 5.0 * axis + 0.01 * Q.col(0));
  r.start(0.0, Vec3::Zero());
  const Vec3 pi0 = r.momentum();
  const double e0 = r.kinetic_energy();
  SpinRun out;
  double last = 1;
  for (int n = 1; n * h <= T + 1e-12; ++n) {
    const double t = n * h;
    r.commit(t, r.orientation(t), Vec3::Zero());
    out.momentum_error = std::max(out.momentum_error, (r.momentum() - pi0).norm() / pi0.norm());
    out.energy_error = std::max(out.energy_error, std::abs(r.kinetic_energy() - e0) / e0);
    // The body's intermediate axis against its start: a flip turns it over.
    const double along = (r.orientation() * axis).dot(axis);
    if (along * last < 0) ++out.flips;
    if (along != 0) last = along;
  }
  return out;
}

TEST(RigidRotation, IntermediateAxisFlipsKeepingMomentumAndEnergy) {
  const SpinRun coarse = spin(2e-3, 20.0), fine = spin(1e-3, 20.0);
  std::cout << "flips " << coarse.flips << ", momentum error " << coarse.momentum_error
            << ", energy error " << coarse.energy_error << " (h = 2e-3), " << fine.energy_error
            << " (h = 1e-3)\n";
  EXPECT_GE(coarse.flips, 3);  // turns over again and again
  EXPECT_EQ(coarse.flips, fine.flips);
  EXPECT_LT(coarse.momentum_error, 1e-12);
  EXPECT_LT(coarse.energy_error, 1e-4);
  // Second order: half the step, about a quarter of the error.
  EXPECT_LT(fine.energy_error, 0.3 * coarse.energy_error);
}

TEST(RigidRotation, MomentTurnsTheBodyAsTheTrapezoidalRule) {
  // A constant moment about z on a sphere: ω(t) = M t / I, the angle M t² / (2 I).
  rigid::Rotation r(2.0 * Mat3::Identity());
  const Vec3 M(0, 0, 0.5);
  r.start(0.0, M);
  const double h = 1e-2;
  for (int n = 1; n <= 100; ++n) r.commit(n * h, r.orientation(n * h), M);
  EXPECT_NEAR(r.angular_velocity().z(), 0.5 * 1.0 / 2.0, 1e-12);
  EXPECT_NEAR(rigid::rotation_vector(r.orientation()).z(), 0.5 / 4.0, 1e-12);
}

}  // namespace
}  // namespace velum
