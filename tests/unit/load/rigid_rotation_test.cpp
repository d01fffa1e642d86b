// The free rigid body's rotation (src/load/rigid_rotation.hpp) without moments: an asymmetric
// body spun about its intermediate axis flips (Dzhanibekov) while its angular momentum is kept
// exactly and its energy within a bound that falls as the step squared; under a moment, the
// work it books (the energy account's) is the change of its kinetic energy.
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

// The moment's work booked at each commit (½ (M_c + M)·θ, what the energy account adds to the
// nodes' work) against the change of the kinetic energy. A sphere: equal to round-off under a
// constant moment (the split is then exact), and under a varying one the difference over the
// run falls as the step squared; torque free, nothing is booked.
struct WorkRun {
  double work = 0, change = 0, worst_step = 0;
};

WorkRun sphere_work(double h, bool varying) {
  rigid::Rotation r(2.0 * Mat3::Identity(), Vec3(0.3, -1.0, 2.0));
  auto moment = [&](double t) {
    return varying ? Vec3(0.5 * std::cos(3 * t), 0.2, -0.1 + 0.3 * t) : Vec3(0.5, 0.2, -0.1);
  };
  r.start(0.0, moment(0));
  WorkRun out;
  const double e0 = r.kinetic_energy();
  for (int n = 1; n * h <= 1 + 1e-12; ++n) {
    const double t = n * h, before = r.kinetic_energy();
    r.commit(t, r.orientation(t), moment(t));
    out.work += r.last_work();
    out.worst_step =
        std::max(out.worst_step, std::abs(r.kinetic_energy() - before - r.last_work()));
  }
  out.change = r.kinetic_energy() - e0;
  return out;
}

TEST(RigidRotation, BookedWorkIsTheKineticEnergysChange) {
  const WorkRun c = sphere_work(1e-2, false);
  const WorkRun v1 = sphere_work(1e-2, true), v2 = sphere_work(5e-3, true);
  std::cout << "sphere, constant moment: kinetic energy change " << c.change << ", work booked "
            << c.work << " (largest step difference " << c.worst_step
            << "); varying moment: " << v1.change - v1.work << " (h = 1e-2), "
            << v2.change - v2.work << " (h = 5e-3)\n";
  EXPECT_GT(std::abs(c.work), 0.1);
  EXPECT_LT(c.worst_step, 1e-13);
  EXPECT_LT(std::abs(v1.change - v1.work), 1e-3 * std::abs(v1.change));
  EXPECT_LT(std::abs(v2.change - v2.work), 0.3 * std::abs(v1.change - v1.work));
  rigid::Rotation free(Vec3(1.0, 2.0, 3.0).asDiagonal(), Vec3(1, 2, 3));
  free.start(0, Vec3::Zero());
  free.commit(0.1, free.orientation(0.1), Vec3::Zero());
  EXPECT_EQ(free.last_work(), 0.0);
}

}  // namespace
}  // namespace velum
