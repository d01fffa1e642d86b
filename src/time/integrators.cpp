#include "velum/time/integrators.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "velum/math/threads.hpp"
#include "velum/time/low_rank_solver.hpp"
#include "velum/time/newton.hpp"
#include "velum/time/secant_updates.hpp"

namespace velum {
namespace {

// A converged static state that turned an element inside out since the step's start is no
// solution: the step fails (and is retried from the last state, or shorter). Dynamic runs
// only warn (the analysis does): a slack sheet held in its plane folds that way.
void reject_inversion(const SecondOrderSystem& sys, double t0, const VecX& u0, double t1,
                      const VecX& u1, StepReport& rep) {
  if (!rep.converged) return;
  if (std::string inv = sys.inverted_element(t0, u0, t1, u1); !inv.empty()) {
    rep.converged = false;
    rep.reason = "Newton converged on a state in which " + inv;
  }
}

}  // namespace

StepReport TimeIntegrator::start(SecondOrderSystem& sys, LinearSolver& solver, double t, State& s) {
  // M a0 = f_ext − f_int − C v0: one linear solve with the Jacobian shifted to M alone.
  StepReport rep;
  if (sys.global_size() == 0) {  // every motion prescribed: nothing to accelerate
    s.a = VecX::Zero(sys.size());
    rep.converged = true;
    return rep;
  }
  SparseMatrix J;
  VecX r, zero = VecX::Zero(sys.size()), da;
  sys.evaluate(t, s.u, s.v, zero, 0.0, 0.0, 1.0, r, &J);
  if (!newton_correction(sys, solver, J, r, da, rep.reason)) {
    rep.reason = "initial acceleration: " + rep.reason;
    return rep;
  }
  s.a = da;
  rep.converged = true;
  return rep;
}

GeneralizedAlpha::GeneralizedAlpha(double am, double af, double b, double g, std::string name)
    : alpha_m(am), alpha_f(af), beta(b), gamma(g), name_(std::move(name)) {}

std::unique_ptr<GeneralizedAlpha> GeneralizedAlpha::chung_hulbert(double rho) {
  const double am = (2 * rho - 1) / (rho + 1), af = rho / (rho + 1);
  const double g = 0.5 - am + af;
  return std::make_unique<GeneralizedAlpha>(am, af, 0.25 * (1 - am + af) * (1 - am + af), g,
                                            "generalized-alpha");
}

std::unique_ptr<GeneralizedAlpha> GeneralizedAlpha::hht(double a) {
  return std::make_unique<GeneralizedAlpha>(0.0, a, 0.25 * (1 + a) * (1 + a), 0.5 + a, "hht");
}

std::unique_ptr<GeneralizedAlpha> GeneralizedAlpha::newmark(double b, double g) {
  return std::make_unique<GeneralizedAlpha>(0.0, 0.0, b, g, "newmark");
}

StepReport GeneralizedAlpha::step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                                  State& s) {
  un_ = s.u, vn_ = s.v, an_ = s.a;
  const double tf = t + (1 - alpha_f) * h;
  const Vec3 coefficients = shift(h);
  const double cu = coefficients[0], cv = coefficients[1], ca = coefficients[2];
  VecX a(un_.size()), v(un_.size());
  auto kinematics = [&](const VecX& u) {
    a = (u - un_ - h * vn_ - (0.5 - beta) * h * h * an_) / (beta * h * h);
    v = vn_ + h * ((1 - gamma) * an_ + gamma * a);
  };
  // Predictor: constant acceleration.
  VecX u = un_ + h * vn_ + 0.5 * h * h * an_;
  // The last step's factorisation is this step's first tangent when nothing has factorised
  // since, the shift (the step size) is the same and the last step converged with at most one
  // factorisation: a chord step tells whether it still is. (On the C9 canopy a carried
  // factorisation cut the residual tenfold in 161 of 181 steps after such an easy step, and
  // in 3 of 89 after a step that took four or more: the inflation, where the wrinkled sheet's
  // tangent changes within a step.)
  if (!low_rank_ || &low_rank_->wrapped() != &solver || &low_rank_->system() != &sys) {
    low_rank_ = std::make_unique<LowRankCorrectedSolver>(solver, sys);
    carried_count_ = -1;
  }
  const bool carried = newton.reuse_across_steps && solver.factorizations() == carried_count_ &&
                       carried_shift_ == Vec3(cu, cv, ca) && work_.J.rows() == un_.size() &&
                       last_factorizations_ <= 1;
  StepReport rep = NewtonSolver(sys, *low_rank_, newton)
                       .solve(un_, u, work_,
                              [&](const VecX& x, VecX& r, SparseMatrix* J) {
                                kinematics(x);
                                uf_ = (1 - alpha_f) * x + alpha_f * un_;
                                vf_ = (1 - alpha_f) * v + alpha_f * vn_;
                                am_ = (1 - alpha_m) * a + alpha_m * an_;
                                sys.evaluate(tf, uf_, vf_, am_, cu, cv, ca, r, J);
                              },
                              {.line_search_by_default = false, .carried = carried});
  carried_count_ = solver.factorizations();
  carried_shift_ = Vec3(cu, cv, ca);
  last_factorizations_ = rep.factorizations;
  if (rep.converged) {
    kinematics(u);
    s.u = u, s.v = v, s.a = a;
  }
  return rep;
}

StepReport CentralDifference::start(SecondOrderSystem& sys, LinearSolver&, double t, State& s) {
  zero_ = VecX::Zero(sys.size());
  sys.evaluate(t, s.u, s.v, zero_, 0, 0, 0, r_, nullptr);
  s.a = -r_.cwiseQuotient(sys.lumped_mass());
  StepReport rep;
  rep.converged = sys.all_finite(s.a);
  if (!rep.converged)
    rep.reason =
        "a node without mass: central difference needs a positive lumped mass at every free DOF";
  return rep;
}

StepReport CentralDifference::step(SecondOrderSystem& sys, LinearSolver&, double t, double h,
                                   State& s) {
  // v(n+½) = v + h/2 a; u(n+1) = u + h v(n+½); a(n+1) from M a = f_ext − f_int − C v(n+½).
  // Two passes over the equations, into buffers kept between steps (swapped with the state's
  // on success: nothing allocated): v(n+½) and u(n+1) in one, a(n+1), v(n+1) and the
  // finiteness test in the other; each shared between the threads (entry by entry: the same
  // bits whatever their number).
  StepReport rep;
  const Eigen::Index n = s.u.size();
  const double hh = 0.5 * h;
  vhalf_.resize(n), u_.resize(n), a_.resize(n), v_.resize(n);
  parallel_ranges(n, [&](long first, long last) {
    for (long i = first; i < last; ++i) {
      vhalf_[i] = s.v[i] + hh * s.a[i];
      u_[i] = s.u[i] + h * vhalf_[i];
    }
  });
  if (zero_.size() != sys.size()) zero_.setZero(sys.size());  // read only
  sys.evaluate(t + h, u_, vhalf_, zero_, 0, 0, 0, r_, nullptr);
  const VecX& m = sys.lumped_mass();
  const double non_finite = parallel_sum(n, [&](long first, long last) {
    bool finite = true;
    for (long i = first; i < last; ++i) {
      a_[i] = -r_[i] / m[i];
      v_[i] = vhalf_[i] + hh * a_[i];
      finite = finite && std::isfinite(a_[i]);
    }
    return finite ? 0.0 : 1.0;
  });
  const bool finite = non_finite == 0;
  if (sys.max_over_processes(finite ? 0.0 : 1.0) != 0.0) {
    rep.reason = "non-finite acceleration (step above the stable limit?)";
    return rep;
  }
  s.u.swap(u_);
  s.v.swap(v_);
  s.a.swap(a_);
  rep.converged = true;
  return rep;
}

bool StaticNewton::predict(const SecondOrderSystem& sys, double t, double h, const State& s,
                           VecX& u) {
  // Extrapolate only along increments that ended where this step starts (not after a
  // restart or a change of state from outside): linearly along the last one, or along the
  // parabola through the last three states. The one taken is the one that would have left the
  // smaller residual at the start of the last increment: a smooth load path favours the
  // parabola (its error is third order in the step), a kink in it or a first, stress-free
  // increment the line. The residual, not the distance, because the in-plane error it weighs
  // most sets the stresses and through them the tangent the chord steps reuse.
  // The sizes judged on every process alike (one with no local equations holds empty ones).
  auto fits = [&](const VecX& x) {
    return sys.sum_over_processes(x.size() == s.u.size() ? 0.0 : 1.0) == 0.0;
  };
  continuous_ = h_prev_ > 0 && std::abs(t - t_prev_) <= 1e-12 * (1 + std::abs(t)) && fits(u_prev_);
  const bool extrapolate = extrapolate_ && continuous_;
  second_ = extrapolate && h_prev2_ > 0 && fits(u_prev2_);
  if (extrapolate) linear_ = s.u + (h / h_prev_) * (s.u - u_prev_);
  if (second_) {
    // Lagrange through (t − h_prev − h_prev2, u_prev2), (t − h_prev, u_prev), (t, u) at t + h.
    const double a = h_prev2_, b = h_prev_;
    const double c2 = h * (h + b) / ((a + b) * a), c1 = -h * (h + a + b) / (a * b),
                 c0 = (h + b) * (h + a + b) / ((a + b) * b);
    parabolic_ = c2 * u_prev2_ + c1 * u_prev_ + c0 * s.u;
  }
  u = !extrapolate ? s.u : second_ && prefer_parabola_ ? parabolic_ : linear_;
  // A predictor that turns an element inside out has left the path: start from the last state.
  if (extrapolate && !sys.inverted_element(t, s.u, t + h, u).empty()) {
    u = s.u;
    return false;
  }
  return extrapolate;
}

void StaticNewton::record_inertia(SecondOrderSystem& sys, LinearSolver& solver, double t,
                                  const VecX& u, StepReport& rep) {
  if (sys.global_size() == 0) {  // every motion prescribed: no stiffness to be indefinite
    rep.negative_pivots = 0;
    return;
  }
  rep.negative_pivots = solver.negative_pivots();
  // The count is that of the last tangent factorised, at an iterate near u; where it differs
  // from the last step's (a critical point may lie between), it is made exact at u itself,
  // as it is where this step factorised nothing (it started in equilibrium).
  const bool changed = rep.negative_pivots >= 0 && rep.negative_pivots != negative_pivots_;
  if (rep.factorizations > 0 && !changed) return;
  sys.evaluate(t, u, zero_, zero_, 1.0, 0.0, 0.0, work_.r, &work_.J);
  ++rep.factorizations;
  rep.negative_pivots =
      solver.refactorize(work_.J, sys.pattern_revision()) ? solver.negative_pivots() : -1;
}

void StaticNewton::remember(const SecondOrderSystem& sys, double t, double h, const VecX& u_start,
                            const VecX& u, const StepReport& rep) {
  if (second_) {  // the residual each predictor left, to first order: J times its error
    linear_ -= u;
    parabolic_ -= u;
    // Both products in one walk of J (the largest thing here), each entry summed in the order
    // of Eigen's product.
    VecX& by_line = left_by_line_;
    VecX& by_parabola = left_by_parabola_;
    by_line.setZero(work_.J.rows());
    by_parabola.setZero(work_.J.rows());
    const int* outer = work_.J.outerIndexPtr();
    const int* inner = work_.J.innerIndexPtr();
    const double* value = work_.J.valuePtr();
    for (int j = 0; j < work_.J.outerSize(); ++j) {
      const double a = linear_[j], b = parabolic_[j];
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        by_line[inner[k]] += value[k] * a;
        by_parabola[inner[k]] += value[k] * b;
      }
    }
    sys.complete(by_line);  // the tangent may be this process's share
    sys.complete(by_parabola);
    prefer_parabola_ = sys.squared_norm(by_parabola) < sys.squared_norm(by_line);
  } else {
    prefer_parabola_ = false;
  }
  if (continuous_) {
    std::swap(u_prev2_, u_prev_);
    h_prev2_ = h_prev_;
  } else {
    h_prev2_ = 0;
  }
  u_prev_ = u_start;
  h_prev_ = h;
  t_prev_ = t + h;
  negative_pivots_ = rep.negative_pivots;
}

StepReport StaticNewton::step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                              State& s) {
  zero_.setZero(sys.size());
  // Newton from u; a converged state that turned an element inside out is no solution.
  auto solve_from = [&](VecX& u) {
    // Every solve, Newton or chord, with the system's low-rank Jacobian part (enclosed gas).
    LowRankCorrectedSolver low_rank(solver, sys);
    StepReport rep = NewtonSolver(sys, low_rank, newton)
                         .solve(s.u, u, work_,
                                [&](const VecX& x, VecX& r, SparseMatrix* J) {
                                  sys.evaluate(t + h, x, zero_, zero_, 1.0, 0.0, 0.0, r, J);
                                },
                                {.line_search_by_default = true,
                                 .secant = newton.reuse_tangent ? &secant_ : nullptr});
    reject_inversion(sys, t, s.u, t + h, u, rep);
    if (rep.converged) record_inertia(sys, solver, t + h, u, rep);
    return rep;
  };
  VecX u;
  const bool extrapolated = predict(sys, t, h, s, u);
  StepReport rep = solve_from(u);
  // From an extrapolated start, a failure, or a state less stable than the last (more
  // negative eigenvalues: the predictor carried the step over a limit point onto another
  // branch), is retried from the last state, which keeps the branch the path is on.
  const bool less_stable =
      rep.converged && negative_pivots_ >= 0 && rep.negative_pivots > negative_pivots_;
  if (extrapolated && !rep.interrupted && (!rep.converged || less_stable)) {
    const int seen = rep.negative_pivots_seen;
    VecX u_plain = s.u;
    StepReport plain = solve_from(u_plain);
    const int iterations = rep.iterations + plain.iterations,
              factorizations = rep.factorizations + plain.factorizations;
    if (plain.converged || !rep.converged) {  // residuals in the order they came
      plain.residuals.insert(plain.residuals.begin(), rep.residuals.begin(), rep.residuals.end());
      rep = std::move(plain);
      u = std::move(u_plain);
    } else {  // the extrapolated state kept: its residuals last, ending on the converged one
      rep.residuals.insert(rep.residuals.begin(), plain.residuals.begin(), plain.residuals.end());
    }
    rep.iterations = iterations;
    rep.factorizations = factorizations;
    rep.negative_pivots_seen = std::max(rep.negative_pivots_seen, seen);
  }
  if (rep.converged && negative_pivots_ == 0 && rep.negative_pivots == 0 &&
      rep.negative_pivots_seen > 0) {
    // Stable to stable through an indefinite tangent: a jump over a limit point when the
    // increment is far beyond the last one's (scaled to this step); a load that turns back
    // short of the limit moves about as far as before. Without a last increment, told.
    const bool last =
        continuous_ && sys.sum_over_processes(u_prev_.size() == s.u.size() ? 0.0 : 1.0) == 0.0;
    rep.branch_jump = !last || sys.norm(u - s.u) > 5 * (h / h_prev_) * sys.norm(s.u - u_prev_);
  }
  if (rep.converged) {
    remember(sys, t, h, s.u, u, rep);
    s.u = u;
  } else if (!rep.interrupted && negative_pivots_ == 0 && rep.negative_pivots_seen > 0) {
    // From a stable state the iterations wandered onto an indefinite tangent and found no
    // equilibrium: the load has passed its limit on this branch, where a smaller step only
    // comes closer to the limit point and load control cannot go on.
    rep.reason = fmt::format(
        "the load passes a limit point near t = {:.6g}: beyond it there is no equilibrium near "
        "this branch (the tangent stiffness turned indefinite in the iterations, {} negative "
        "eigenvalue{}), and a smaller step cannot help; follow the path with analysis.path "
        "(arc_length) or run a dynamic analysis ({})",
        t, rep.negative_pivots_seen, rep.negative_pivots_seen == 1 ? "" : "s", rep.reason);
  }
  return rep;
}

std::vector<double> StaticNewton::save(const SecondOrderSystem& sys) const {
  // Empty or the system's size on every process alike (the same steps were taken; a process
  // with no local equations holds empty ones either way).
  auto held = [&](const VecX& x) { return sys.sum_over_processes(x.size() ? 1.0 : 0.0) > 0; };
  const VecX u1 = held(u_prev_) ? sys.to_global(u_prev_) : VecX(),
             u2 = held(u_prev2_) ? sys.to_global(u_prev2_) : VecX();
  std::vector<double> m = {h_prev_,
                           h_prev2_,
                           t_prev_,
                           prefer_parabola_ ? 1.0 : 0.0,
                           static_cast<double>(negative_pivots_),
                           static_cast<double>(u1.size()),
                           static_cast<double>(u2.size())};
  m.insert(m.end(), u1.data(), u1.data() + u1.size());
  m.insert(m.end(), u2.data(), u2.data() + u2.size());
  return m;
}

void StaticNewton::restore(const SecondOrderSystem& sys, const std::vector<double>& m) {
  if (m.size() < 7) throw std::invalid_argument("static predictor memory: too short");
  const auto n1 = static_cast<Eigen::Index>(m[5]), n2 = static_cast<Eigen::Index>(m[6]);
  if (m.size() != static_cast<size_t>(7 + n1 + n2))
    throw std::invalid_argument("static predictor memory: wrong size");
  h_prev_ = m[0], h_prev2_ = m[1], t_prev_ = m[2];
  prefer_parabola_ = m[3] != 0;
  negative_pivots_ = static_cast<int>(m[4]);
  u_prev_ = Eigen::Map<const VecX>(m.data() + 7, n1);
  u_prev2_ = Eigen::Map<const VecX>(m.data() + 7 + n1, n2);
  if (n1) u_prev_ = sys.to_local(u_prev_);
  if (n2) u_prev2_ = sys.to_local(u_prev2_);
}

}  // namespace velum
