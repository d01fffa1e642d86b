// The rotation of a free rigid body under the moments of its contact forces (docs/contact.md):
// orientation R and spatial angular momentum π about the centre of mass, advanced by a
// Verlet split on SO(3) whose orientation over a step depends on the committed state only.
#pragma once

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::rigid {

/// exp of the rotation vector θ (radians): the rotation by |θ| about θ.
inline Mat3 rotation_matrix(const Vec3& theta) {
  const double a = theta.norm();
  if (a == 0) return Mat3::Identity();
  return Eigen::AngleAxisd(a, theta / a).toRotationMatrix();
}

/// The rotation vector of R (log: the angle in [0, π]).
inline Vec3 rotation_vector(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// A body's rotational state, committed at accepted steps. From the committed (R, π, M) at
/// t_c, the orientation at t = t_c + τ is
///   π½ = π + τ/2 M,   θ = τ I(R½)⁻¹ π½ with R½ = exp(θ/2) R (solved for θ),   R(t) = exp(θ) R,
/// and at the step's acceptance π(t) = π½ + τ/2 M(t) (M(t) the moment about the centre at the
/// accepted state). I(R) = R J₀ Rᵀ, J₀ the inertia in the global axes at t = 0. Symmetric in
/// time (second order, no drift of the energy), π kept exactly without moments.
class Rotation {
 public:
  Rotation() = default;
  explicit Rotation(const Mat3& J0, const Vec3& omega0 = Vec3::Zero())
      : J0_(J0), J0_inv_(J0.inverse()), pi_(J0 * omega0) {}

  /// The orientation at t (the committed one at t = time()).
  Mat3 orientation(double t) const {
    const double tau = t - t_;
    const Mat3 R = q_.toRotationMatrix();
    if (tau == 0) return R;
    const Vec3 half = pi_ + 0.5 * tau * M_;
    auto omega = [&](const Vec3& theta) {  // I(R½)⁻¹ π½
      const Mat3 Rm = rotation_matrix(0.5 * theta) * R;
      return Vec3(Rm * (J0_inv_ * (Rm.transpose() * half)));
    };
    // Newton on G(θ) = θ − τ ω(θ), its 3 x 3 derivative by central differences; from the
    // explicit θ = τ I(R)⁻¹ π½.
    Vec3 theta = tau * omega(Vec3::Zero());
    for (int it = 0; it < 50; ++it) {
      const Vec3 G = theta - tau * omega(theta);
      if (G.norm() <= 1e-15 * (1e-300 + theta.norm())) break;
      const double e = 1e-6 * std::max(theta.norm(), 1e-6);
      Mat3 D;
      for (int c = 0; c < 3; ++c) {
        const Vec3 d = e * Vec3::Unit(c);
        D.col(c) = Vec3::Unit(c) - tau * (omega(theta + d) - omega(theta - d)) / (2 * e);
      }
      const Vec3 step = D.partialPivLu().solve(G);
      theta -= step;
      if (step.norm() <= 1e-15 * theta.norm()) break;
    }
    return rotation_matrix(theta) * R;
  }
  /// The step to t accepted: R at t (from orientation(t)), M the moment about the centre there.
  /// Also books the moment's work over the step: ½ (M_c + M)·θ, θ the rotation vector of
  /// R R_cᵀ (the trapezoidal rule, as the nodes' work is booked).
  void commit(double t, const Mat3& R, const Vec3& M) {
    const double tau = t - t_;
    work_ = 0.5 * (M_ + M).dot(rotation_vector(R * orientation().transpose()));
    pi_ += 0.5 * tau * (M_ + M);
    q_ = Eigen::Quaterniond(R).normalized();
    M_ = M;
    t_ = t;
  }
  /// Where the analysis starts: the committed time t, the moment M at the start.
  void start(double t, const Vec3& M) { t_ = t, M_ = M, work_ = 0; }

  double time() const { return t_; }
  Mat3 orientation() const { return q_.toRotationMatrix(); }
  const Vec3& momentum() const { return pi_; }
  const Vec3& moment() const { return M_; }
  /// The inertia about the centre in the global axes at the committed orientation.
  Mat3 inertia() const {
    const Mat3 R = orientation();
    return R * J0_ * R.transpose();
  }
  Vec3 angular_velocity() const {
    const Mat3 R = orientation();
    return R * (J0_inv_ * (R.transpose() * pi_));
  }
  double kinetic_energy() const { return 0.5 * pi_.dot(angular_velocity()); }
  /// The moment's work over the last committed step (0 before one, and after a restore).
  double last_work() const { return work_; }
  /// The least principal moment (the explicit step's bound).
  double least_inertia() const {
    return Eigen::SelfAdjointEigenSolver<Mat3>(J0_, Eigen::EigenvaluesOnly).eigenvalues()[0];
  }

  /// The committed state as kSaved numbers (quaternion w x y z, π, M, t), and back.
  void save(std::vector<double>& out) const {
    out.insert(out.end(),
               {q_.w(), q_.x(), q_.y(), q_.z(), pi_[0], pi_[1], pi_[2], M_[0], M_[1], M_[2], t_});
  }
  size_t restore(const std::vector<double>& in, size_t at) {
    q_ = Eigen::Quaterniond(in[at], in[at + 1], in[at + 2], in[at + 3]);
    pi_ = Vec3(in[at + 4], in[at + 5], in[at + 6]);
    M_ = Vec3(in[at + 7], in[at + 8], in[at + 9]);
    t_ = in[at + 10];
    work_ = 0;
    return at + 11;
  }
  static constexpr size_t kSaved = 11;

 private:
  Mat3 J0_ = Mat3::Identity(), J0_inv_ = Mat3::Identity();
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Vec3 pi_ = Vec3::Zero(), M_ = Vec3::Zero();
  double t_ = 0, work_ = 0;
};

/// A rotating free body's rotation shared by the contact entries it takes part in: each adds
/// its contact moment about the centre (and its stiffness against turning, Σ k r²) at the state
/// being started or accepted, and the last of the `entries` moves the rotation on with the sum
/// (contact_load.cpp). The first entry saves it and reports its energy.
struct Spin {
  Spin(const Mat3& J0, const Vec3& omega0) : rot(J0, omega0) {}
  Rotation rot;
  Vec3 moment = Vec3::Zero();
  double turning = 0;
  int entries = 1, added = 0;
  double step_ratio = 0;  ///< the largest step over the rotation's stable step
};

}  // namespace velum::rigid
