#include "explicit_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace velum {

namespace {

// The step on a grid of 512 steps per octave, rounded down (at most 0.14 % shorter). The
// estimate is a power iteration converged to about 1e-10, and on several processes its sums
// run in another order: unsnapped, one and two processes took steps 7e-11 apart and their
// contact histories drifted 3.5e-8 apart over 2,300 steps (tests/parallel/mpi_explicit.py).
double snapped(double h) {
  if (!(h > 0) || !std::isfinite(h)) return h;
  constexpr double kPerOctave = 512;
  return std::exp2(std::floor(std::log2(h) * kPerOctave) / kPerOctave);
}

}  // namespace

double ExplicitStepControl::set_step(double estimate) {
  const double safe = settings_.explicit_step.safety * estimate;
  // Mass scaling's target is reached whatever the grid (one process only).
  const double floor = std::min(settings_.explicit_step.target_step, safe);
  const double h = std::min(settings_.time.step, std::max(snapped(safe), floor));
  report_.last = estimate;
  ++report_.estimates;
  report_.smallest = report_.smallest > 0 ? std::min(report_.smallest, h) : h;
  report_.largest = std::max(report_.largest, h);
  return h;
}

double ExplicitStepControl::start(double t, const State& s) {
  report_.first = estimate_.start(sys_, t, s);
  if (settings_.explicit_step.target_step > 0) {
    scale_mass();
    report_.first = estimate_.restart(sys_);  // the same stiffness, the new mass
  }
  return set_step(report_.first);
}

// Each node gets at least the mass that brings its rows' Gershgorin bound under the target's
// ω²: m ≥ g_i (h_target / (2 safety))² over its equations i. Then every row of M⁻¹K is,
// and with them ω_max² (Gershgorin), so that safety x 2/ω_max reaches the target.
void ExplicitStepControl::scale_mass() {
  if (sys_.distributed())
    throw std::invalid_argument(
        "analysis.integrator.mass_scaling runs on one process only (not under mpirun yet)");
  const ExplicitStepSettings& x = settings_.explicit_step;
  const double c = x.target_step / (2 * x.safety);
  const VecX g = stiffness_row_bounds(estimate_.stiffness(), sys_.jacobian_low_rank());
  const VecX& m = sys_.node_mass();
  report_.model_mass = m.sum();
  VecX least = VecX::Zero(m.size());
  const DofMap& dofs = sys_.dofs();
  for (int n = 0; n < sys_.model().num_nodes(); ++n)
    for (int k = 0; k < 3; ++k)
      if (const int eq = dofs.equation(n, k); eq >= 0) least[n] = std::max(least[n], g[eq] * c * c);
  added_ = (least - m).cwiseMax(0.0);
  report_.added_mass = added_.sum();
  report_.scaled_nodes = static_cast<int>((added_.array() > 0).count());
  if (report_.added_mass > 0) sys_.add_node_mass(added_);
  warn_(fmt::format(
      "mass scaling to a step of {:.6g}: {:.6g} added to {} node{} ({:.3g}% of the model's mass "
      "{:.6g}): the inertia is no longer the model's",
      x.target_step, report_.added_mass, report_.scaled_nodes, report_.scaled_nodes == 1 ? "" : "s",
      report_.model_mass > 0 ? 100 * report_.added_mass / report_.model_mass : 0.0,
      report_.model_mass));
}

double ExplicitStepControl::update(double t, double h, const State& s, double last_step) {
  if (!settings_.explicit_step.from_current_state || ++since_ < stride_) return last_step;
  since_ = 0;
  const double before = estimate_.omega_squared();
  const double step = set_step(estimate_.update(sys_, t, h, s));
  report_.evaluations = estimate_.evaluations();
  const double now = estimate_.omega_squared();
  const double moved = now > 0 ? std::abs(now - before) / now : 1.0;
  if (moved < 0.01)
    stride_ = std::min(2 * stride_, kMaxStride);
  else if (moved > 0.02)
    stride_ = 1;
  return step;
}

void ExplicitStepControl::save(std::vector<double>& m) const {
  m.insert(m.end(), {static_cast<double>(stride_), static_cast<double>(since_)});
  estimate_.save(sys_, m);
  m.push_back(static_cast<double>(added_.size()));
  m.insert(m.end(), added_.data(), added_.data() + added_.size());
}

void ExplicitStepControl::restore(const std::vector<double>& m, size_t at) {
  if (m.size() < at + 2) return;  // nothing saved: start afresh
  stride_ = static_cast<int>(m[at]), since_ = static_cast<int>(m[at + 1]);
  at += 2;
  at = estimate_.restore(sys_, m, at);
  if (m.size() <= at) return;
  const auto n = static_cast<size_t>(m[at]);
  if (m.size() < at + 1 + n || (n != 0 && static_cast<int>(n) != sys_.model().num_nodes()))
    throw std::invalid_argument("checkpoint: the mass added does not fit this model");
  if (n == 0) return;
  added_.resize(static_cast<Eigen::Index>(n));
  std::copy(m.begin() + static_cast<long>(at) + 1, m.begin() + static_cast<long>(at + 1 + n),
            added_.data());
  sys_.add_node_mass(added_);
  report_.added_mass = added_.sum();
  report_.scaled_nodes = static_cast<int>((added_.array() > 0).count());
  report_.model_mass = sys_.node_mass().sum() - report_.added_mass;
}

}  // namespace velum
