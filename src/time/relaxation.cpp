#include "velum/time/relaxation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace velum {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

bool DynamicRelaxation::out_of_time(const SecondOrderSystem& sys, double rn, std::string& why) {
  if (newton.interrupt_requested()) {
    interrupted_ = true;
    why = "interrupted";
    return true;
  }
  // Several processes: each one's clock, the decision together (any one spent ends it).
  if (relaxation.max_seconds > 0 &&
      sys.sum_over_processes(seconds_now() - level_start_ > relaxation.max_seconds ? 1.0 : 0.0) >
          0) {
    spent_ = true;
    why = fmt::format(
        "dynamic relaxation: the load level was not relaxed within analysis.relaxation."
        "max_seconds = {:g} s ({} iterations; residual {:.3e}, scale {:.3e})",
        relaxation.max_seconds, iterations_, rn, ref_);
    return true;
  }
  return false;
}

void DynamicRelaxation::update_masses(SecondOrderSystem& sys, double t, const VecX& u) {
  const int n = sys.size();
  sys.evaluate(t, u, zero_, zero_, 1.0, 0.0, 0.0, r_, &J_);
  VecX rows = VecX::Zero(n);
  for (int k = 0; k < J_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(J_, k); it; ++it) rows[it.row()] += std::abs(it.value());
  sys.complete(rows);  // J may be this process's share
  // The low-rank part of the Jacobian (an enclosed gas: (γ p / V) a aᵀ) belongs to the row
  // sums as much as the sparse part: without it the masses are too light for the gas's
  // stiffness of the volume, and a chamber started far from its volume oscillates.
  const LowRankJacobian& low = sys.jacobian_low_rank();
  for (Eigen::Index j = 0; j < low.U.cols(); ++j)
    rows += low.U.col(j).cwiseAbs() * sys.sum(low.W.col(j).cwiseAbs());
  const auto& groups = sys.equation_groups();
  if (!groups.empty()) {
    const int ng = *std::max_element(groups.begin(), groups.end()) + 1;
    VecX gmax = VecX::Zero(ng);
    for (int i = 0; i < n; ++i) gmax[groups[i]] = std::max(gmax[groups[i]], rows[i]);
    for (int i = 0; i < n; ++i) rows[i] = gmax[groups[i]];
  }
  // A node whose equations have almost no stiffness yet (the centre of a flat sheet held on
  // two symmetry planes keeps only its normal component) would take a huge first step into a
  // stiffness it did not know of: no mass is lighter than a tenth of the mean.
  const double mean =
      sys.global_size() > 0 ? sys.sum(rows) / static_cast<double>(sys.global_size()) : 0.0;
  m_ = 0.5 * rows.cwiseMax(mean > 0 ? 0.1 * mean : 1.0);
}

bool DynamicRelaxation::relax(SecondOrderSystem& sys, double t, VecX& u, double rel_target,
                              long budget, std::string& why) {
  const int n = sys.size();
  v_.setZero(n);
  VecX u_peak = u;
  double ke = 0, r_peak = -1;
  bool restart = true;
  long since_masses = 0;
  update_masses(sys, t, u);
  for (long it = 0; it < budget; ++it) {
    sys.evaluate(t, u, zero_, zero_, 1.0, 0.0, 0.0, r_, nullptr);
    const double rn = sys.norm(r_);
    if (!std::isfinite(rn)) {
      why = fmt::format("dynamic relaxation: non-finite residual after {} iterations", iterations_);
      return false;
    }
    ++iterations_;
    ++since_masses;
    // The scale the residual is judged against: the forces of the state at hand and the
    // imbalance the load level started from. Not a running maximum: the forces of a
    // transient that the guard below undoes must not loosen the target.
    if (ref_ == 0) ref_ = std::max(rn, sys.force_scale());
    if (it == 0) r_peak = rn;
    const double scale = std::max(ref_, sys.force_scale());
    const double target = ConvergenceTest(rel_target, newton.abs_residual)
                              .target_against(scale, sys.residual_noise());
    if (rn <= target) return true;
    if (out_of_time(sys, rn, why)) return false;
    // A residual far above the one at the last peak: the masses are too light for the
    // stiffness reached (it grows as the sheet tightens). Back to the peak, heavier masses.
    if (r_peak > 0 && rn > 1e3 * r_peak) {
      u = u_peak;
      v_.setZero();
      ke = 0;
      restart = true;
      // Four times the masses that were too light, not four times the tangent's again (the
      // same masses when nothing changed: a sheet slack everywhere, whose every point's
      // stiffness is the residual κ Q, fired the guard every third iteration for ever). The
      // next update at a peak goes back to the tangent's.
      m_ *= 4;
      since_masses = 0;
      continue;
    }
    // Half-step velocities: v(n+½) = v(n−½) + M⁻¹ R(n), R = −r, Δτ = 1; v(½) = ½ M⁻¹ R(0).
    const double first = restart ? 0.5 : 1.0;
    double ke_new = 0;
    for (int i = 0; i < sys.owned_size(); ++i) {  // the ghosts are another process's
      const double vi = (restart ? 0.0 : v_[i]) - first * r_[i] / m_[i];
      ke_new += 0.5 * m_[i] * vi * vi;
    }
    ke_new = sys.sum_over_processes(ke_new);
    if (!restart && ke_new < ke) {
      // Kinetic energy peaked between the half steps: the peak lies at x(n) − ½ v(n−½)
      // (Barnes's correction for a kinetic energy quadratic in time). Start again from rest.
      u -= 0.5 * v_;
      v_.setZero();
      ke = 0;
      restart = true;
      ++peaks_;
      u_peak = u;
      r_peak = rn;
      if (since_masses >= 10) {
        update_masses(sys, t, u);
        since_masses = 0;
      }
      continue;
    }
    for (int i = 0; i < n; ++i) v_[i] = (restart ? 0.0 : v_[i]) - first * r_[i] / m_[i];
    ke = ke_new;
    restart = false;
    u += v_;
  }
  why = fmt::format(
      "dynamic relaxation did not reach {:.1e} of the force scale in {} iterations (residual "
      "{:.3e}, scale {:.3e})",
      rel_target, budget, sys.norm(r_), std::max(ref_, sys.force_scale()));
  return false;
}

StepReport DynamicRelaxation::step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                                   State& s) {
  StepReport rep;
  zero_.setZero(sys.size());
  iterations_ = 0;
  peaks_ = 0;
  ref_ = 0;
  level_start_ = seconds_now();
  interrupted_ = spent_ = false;
  VecX u = s.u;
  double rel = std::max(relaxation.newton_switch, newton.tolerance);
  for (;;) {
    std::string why;
    const bool reached = relax(sys, t + h, u, rel, relaxation.max_iterations - iterations_, why);
    rep.iterations = static_cast<int>(std::min<long>(iterations_, 1L << 30));
    if (interrupted_ || spent_) {
      rep.interrupted = interrupted_;
      rep.ends_run = spent_;
      rep.reason = why;
      return rep;
    }
    if (!reached && !sys.all_finite(u)) {
      rep.reason = why;
      return rep;
    }
    if (reached && rel <= newton.tolerance) {  // relaxation alone met the static tolerance
      s.u = u;
      rep.converged = true;
      return rep;
    }
    // Newton from the relaxed state (a fresh static integrator: no predictor history).
    StaticNewton finish;
    finish.newton = newton;
    State trial = s;
    trial.u = u;
    const StepReport nr = finish.step(sys, solver, t, h, trial);
    rep.iterations += nr.iterations;
    rep.factorizations += nr.factorizations;
    rep.residuals.insert(rep.residuals.end(), nr.residuals.begin(), nr.residuals.end());
    if (nr.converged) {
      s.u = trial.u;
      rep.converged = true;
      return rep;
    }
    if (nr.interrupted) {
      rep.interrupted = true;
      rep.reason = nr.reason;
      return rep;
    }
    if (!reached || rel <= newton.tolerance) {
      rep.reason = reached ? nr.reason : why;
      return rep;
    }
    rel = std::max(rel * 1e-2, newton.tolerance);
  }
}

}  // namespace velum
