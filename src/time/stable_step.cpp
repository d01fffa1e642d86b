#include "velum/time/stable_step.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace velum {

double StableStepEstimate::step(const SecondOrderSystem& sys) const {
  // A penalty that is not in touch yet still bounds the step once it is (ω² at most the sum).
  const double lambda = lambda_ + sys.load_stiffness_over_mass();
  return lambda > 0 ? 2.0 / std::sqrt(lambda) : INFINITY;
}

double StableStepEstimate::start(SecondOrderSystem& sys, double t, const State& s) {
  zero_ = VecX::Zero(sys.size());
  if (sys.global_size() == 0) {
    x_.resize(0);
    lambda_ = 0;
    return INFINITY;
  }
  sys.evaluate(t, s.u, s.v, zero_, 1.0, 0.0, 0.0, r_, &K_);
  return restart(sys);
}

double StableStepEstimate::restart(SecondOrderSystem& sys) {
  evaluations_ = 0;
  lambda_ = 0;
  if (sys.global_size() == 0) return INFINITY;
  const LowRankJacobian& L = sys.jacobian_low_rank();
  const VecX& m = sys.lumped_mass();
  // ‖·‖_M: the iteration is that on M^-½ K M^-½, whose norm ratio never exceeds ω_max² for a
  // symmetric K.
  auto m_norm = [&](const VecX& z) { return std::sqrt(sys.dot(z, m.cwiseProduct(z))); };
  x_ = VecX::Ones(sys.size());
  x_ /= m_norm(x_);
  for (int it = 0; it < 50; ++it) {
    y_ = K_ * x_;
    sys.complete(y_);  // K may be this process's share
    if (L.U.cols() > 0) y_.noalias() += L.U * sys.transposed_product(L.W, x_);
    y_.array() /= m.array();
    const double l = m_norm(y_);
    if (!(l > 0) || !std::isfinite(l)) break;
    x_ = y_ / l;
    const bool settled = std::abs(l - lambda_) < 1e-4 * l;
    lambda_ = l;
    if (settled) break;
  }
  return step(sys);
}

double StableStepEstimate::update(SecondOrderSystem& sys, double t, double h, const State& s) {
  if (x_.size() != sys.size() || !(lambda_ > 0)) return start(sys, t, s);
  const VecX& m = sys.lumped_mass();
  auto m_norm = [&](const VecX& z) { return std::sqrt(sys.dot(z, m.cwiseProduct(z))); };
  // The residual at the state, the step's own: M a = −r(u, v½).
  vhalf_ = s.v - 0.5 * h * s.a;
  r0_ = -m.cwiseProduct(s.a);
  if (zero_.size() != sys.size()) zero_.setZero(sys.size());
  // A perturbation of 1e-7 of the model's length scale at its largest component: far above
  // the forces' round-off, far below any change of their slope but a kink's.
  const double scale = std::max(
      sys.max_abs(s.u), sys.reference_position_norm() / std::sqrt(double(sys.global_size())));
  const double length = scale > 0 ? scale : 1.0;
  for (int it = 0; it < kMaxIterations; ++it) {
    const double eps = 1e-7 * length / sys.max_abs(x_);
    u_ = s.u + eps * x_;
    sys.evaluate(t, u_, vhalf_, zero_, 0, 0, 0, r_, nullptr);
    ++evaluations_;
    y_ = (r_ - r0_) / eps;
    y_.array() /= m.array();
    const double l = m_norm(y_);
    if (!(l > 0) || !std::isfinite(l)) break;  // nothing stiff, or a state past saving
    x_ = y_ / l;
    const bool settled = std::abs(l - lambda_) < 2e-2 * l;
    lambda_ = l;
    if (settled) break;
  }
  return step(sys);
}

void StableStepEstimate::save(const SecondOrderSystem& sys, std::vector<double>& m) const {
  const VecX x = x_.size() == sys.size() ? sys.to_global(x_) : VecX();
  m.insert(m.end(), {lambda_, static_cast<double>(evaluations_), static_cast<double>(x.size())});
  m.insert(m.end(), x.data(), x.data() + x.size());
}

size_t StableStepEstimate::restore(const SecondOrderSystem& sys, const std::vector<double>& m,
                                   size_t at) {
  if (m.size() < at + 3) return at;
  const auto n = static_cast<size_t>(m[at + 2]);
  if (m.size() < at + 3 + n || (n != 0 && static_cast<long>(n) != sys.global_size()))
    throw std::invalid_argument("checkpoint: the stable step's estimate does not fit this model");
  lambda_ = m[at];
  evaluations_ = static_cast<long>(m[at + 1]);
  VecX x(static_cast<Eigen::Index>(n));
  std::copy(m.begin() + static_cast<long>(at) + 3, m.begin() + static_cast<long>(at + 3 + n),
            x.data());
  x_ = n ? sys.to_local(x) : VecX();
  return at + 3 + n;
}

double stable_time_step(SecondOrderSystem& sys, double t, const State& s) {
  StableStepEstimate e;
  return e.start(sys, t, s);
}

VecX stiffness_row_bounds(const SparseMatrix& J, const LowRankJacobian& L) {
  VecX g = VecX::Zero(J.rows());
  for (int j = 0; j < J.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(J, j); it; ++it) g[it.row()] += std::abs(it.value());
  for (Eigen::Index k = 0; k < L.U.cols(); ++k)
    g += L.U.col(k).cwiseAbs() * L.W.col(k).cwiseAbs().sum();
  return g;
}

}  // namespace velum
