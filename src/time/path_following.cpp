#include "velum/time/path_following.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "velum/time/low_rank_solver.hpp"
#include "velum/time/newton.hpp"

namespace velum {
namespace {

// How one step's increment is constrained.
enum class Control { kLoad, kArcLength, kDisplacement };

// Steps along the path from the last accepted point (u_, t_). A step computes a candidate
// (cand_u_, cand_t_) and leaves the accepted point alone until accept() is called, so the
// caller can replace a step that overshoots the end by one that lands on it.
class PathTracer {
 public:
  PathTracer(SecondOrderSystem& sys, LinearSolver& solver, const NewtonSettings& newton,
             const PathSettings& path, const State& s, double t0)
      : sys_(sys), solver_(solver, sys), newton_(newton), path_(path), u_(s.u), t_(t0) {
    zero_.setZero(sys.size());
  }

  // A step of `size`: Δt (load control), Δs (arc length) or the controlled equation's Δu.
  StepReport step(Control control, double size);
  // Brings the accepted point to equilibrium at its load t (a start out of equilibrium) by
  // the integrators' Newton, with its line search and chord steps: the bordered corrector
  // of step() has neither, and from a pressurised start its full corrections overshoot.
  StepReport equilibrate();
  void accept() {
    factorised_at_start_ = factorised_at_candidate_;
    du_prev_ = cand_u_ - u_;
    moved_ = true;
    dt_prev_ = cand_t_ - t_;
    u_ = cand_u_;
    t_ = cand_t_;
  }
  const VecX& u() const { return u_; }
  double t() const { return t_; }
  // Whether the accepted point is an equilibrium within the Newton tolerance.
  bool in_equilibrium() {
    sys_.evaluate(t_, u_, zero_, zero_, 1.0, 0.0, 0.0, r_, nullptr);
    const double rn = sys_.norm(r_);
    return rn <= ConvergenceTest(newton_).target_against(sys_.force_scale(), sys_.residual_noise());
  }
  const VecX& candidate_u() const { return cand_u_; }
  double candidate_t() const { return cand_t_; }

 private:
  bool factorise(const SparseMatrix& J, StepReport& rep);
  // ∂r/∂t at (u, t) by a one-sided difference in the direction the path moves in t (the
  // loads' time functions are piecewise linear: exact away from their kinks, and on the
  // side the path is heading at one). Evaluated before the residual and tangent at the same
  // point, whose force scale and round-off level it would otherwise overwrite.
  void load_rate(const VecX& u, double t, VecX& q);
  // The change δt of the load parameter in a correction a + δt b that keeps the constraint;
  // false when the cylinder has no point on that line.
  bool constraint(Control control, double size, const VecX& du, double dt, const VecX& a,
                  const VecX& b, double& delta_t) const;

  SecondOrderSystem& sys_;
  // Every solve with the system's low-rank Jacobian part (an enclosed gas's p(V) coupling),
  // as the integrators' Newton solves.
  LowRankCorrectedSolver solver_;
  const NewtonSettings& newton_;
  const PathSettings& path_;
  VecX u_;
  double t_;
  VecX du_prev_;                          ///< the last accepted increment (direction of travel)
  bool moved_ = false;                    ///< du_prev_ holds one (it may have no local entries)
  double dt_prev_ = 0;                    ///< ... and its change of t
  bool factorised_at_start_ = false;      ///< the solver holds J at (u_, t_)
  bool factorised_at_candidate_ = false;  ///< ... at the candidate (after a converged step)
  VecX cand_u_, pred_u_, zero_, r_, q_, v_, a_, b_, rq_;
  double cand_t_ = 0, pred_t_ = 0;
  SparseMatrix J_;
};

StepReport PathTracer::equilibrate() {
  NewtonWork work;
  VecX u = u_;
  StepReport rep = NewtonSolver(sys_, solver_, newton_)
                       .solve(u_, u, work,
                              [&](const VecX& x, VecX& r, SparseMatrix* J) {
                                sys_.evaluate(t_, x, zero_, zero_, 1.0, 0.0, 0.0, r, J);
                              },
                              {.line_search_by_default = true});
  if (!rep.converged) return rep;
  if (std::string inv = sys_.inverted_element(t_, u_, t_, u); !inv.empty()) {
    rep.converged = false;
    rep.reason = "converged on a state in which " + inv;
    return rep;
  }
  u_ = std::move(u);
  factorised_at_start_ = false;  // the solver holds a tangent near u_, not at it
  return rep;
}

void PathTracer::load_rate(const VecX& u, double t, VecX& q) {
  const double dir = dt_prev_ < 0 ? -1.0 : 1.0;
  const double delta = dir * 1e-7 * std::max(1.0, std::abs(t));
  sys_.evaluate(t + delta, u, zero_, zero_, 1.0, 0.0, 0.0, rq_, nullptr);
  sys_.evaluate(t, u, zero_, zero_, 1.0, 0.0, 0.0, q, nullptr);
  q = (rq_ - q) / delta;
}

bool PathTracer::factorise(const SparseMatrix& J, StepReport& rep) {
  ++rep.factorizations;
  if (solver_.refactorize(J, sys_.pattern_revision())) return true;
  rep.reason = fmt::format("the {} factorisation failed{}", solver_.name(),
                           solver_.status().empty() ? "" : ": " + solver_.status());
  return false;
}

bool PathTracer::constraint(Control control, double size, const VecX& du, double dt, const VecX& a,
                            const VecX& b, double& delta_t) const {
  (void)dt;
  switch (control) {
    case Control::kLoad:
      delta_t = 0;
      return true;
    case Control::kDisplacement:  // the controlled equation's increment stays `size`
      delta_t = -sys_.global_entry(a, path_.equation) / sys_.global_entry(b, path_.equation);
      return std::isfinite(delta_t);
    case Control::kArcLength:
      break;
  }
  if (path_.constraint == PathSettings::Constraint::kRiks) {
    // The correction is normal to the predictor: pred · (a + δt b) = 0.
    delta_t = -sys_.dot(pred_u_, a) / sys_.dot(pred_u_, b);
    return std::isfinite(delta_t);
  }
  // Crisfield: ‖du + a + δt b‖² = Δs², of the two roots the one that turns the increment
  // least (the other goes back along the path).
  const VecX w = du + a;
  const double A = sys_.squared_norm(b), B = 2 * sys_.dot(b, w),
               C = sys_.squared_norm(w) - size * size;
  const double disc = B * B - 4 * A * C;
  if (!(disc >= 0) || !(A > 0)) return false;
  const double root = std::sqrt(disc);
  const double t1 = (-B + root) / (2 * A), t2 = (-B - root) / (2 * A);
  delta_t = sys_.dot(w + t1 * b, du) >= sys_.dot(w + t2 * b, du) ? t1 : t2;
  return true;
}

StepReport PathTracer::step(Control control, double size) {
  StepReport rep;
  // The tangent of the path at the start: J v = −∂r/∂t.
  if (!factorised_at_start_) {
    load_rate(u_, t_, q_);
    sys_.evaluate(t_, u_, zero_, zero_, 1.0, 0.0, 0.0, r_, &J_);
    if (!factorise(J_, rep)) return rep;
  } else {
    load_rate(u_, t_, q_);
  }
  factorised_at_start_ = factorised_at_candidate_ = false;  // corrections factorise others
  if (!solver_.solve(-q_, v_)) {
    rep.reason = "the path's tangent is not finite";
    return rep;
  }
  // Predictor along the tangent.
  double dt = size;
  if (control == Control::kDisplacement) {
    dt = size / sys_.global_entry(v_, path_.equation);
    if (!std::isfinite(dt)) {
      rep.reason = "the controlled displacement does not move with the load";
      return rep;
    }
  } else if (control == Control::kArcLength) {
    dt = size / sys_.norm(v_);
    // Keep going the way the path went: through a limit point t turns back, u goes on.
    const double along = moved_ ? sys_.dot(du_prev_, v_) : 1.0;
    if (along < 0) dt = -dt;
  }
  VecX du = dt * v_;
  pred_u_ = du;
  pred_t_ = dt;
  ConvergenceTest test(newton_);
  double dn = 0;
  for (int it = 0;; ++it) {
    if (newton_.interrupt_requested()) {
      rep.interrupted = true;
      rep.reason = "interrupted";
      return rep;
    }
    cand_u_ = u_ + du;
    cand_t_ = t_ + dt;
    load_rate(cand_u_, cand_t_, q_);
    sys_.evaluate(cand_t_, cand_u_, zero_, zero_, 1.0, 0.0, 0.0, r_, &J_);
    const double rn = sys_.norm(r_);
    rep.residuals.push_back(rn);
    if (!std::isfinite(rn)) {
      rep.reason = fmt::format("non-finite residual at iteration {}", it);
      return rep;
    }
    const double target = test.residual_target(rn, sys_.force_scale(), sys_.residual_noise());
    // The distance left is taken as the last correction's size (no contraction estimate).
    if (it > 0 && ConvergenceTest::met(
                      rn, target, dn,
                      test.distance_target(sys_.norm(du),
                                           sys_.norm(cand_u_) + sys_.reference_position_norm())))
      break;
    if (it == newton_.max_iterations) {
      rep.reason =
          fmt::format("no convergence in {} iterations (residual {:.3e}, reference {:.3e})",
                      newton_.max_iterations, rn, test.reference());
      return rep;
    }
    if (!factorise(J_, rep)) return rep;
    if (!solver_.solve(-r_, a_) || !solver_.solve(-q_, b_)) {
      rep.reason = "the correction is not finite";
      return rep;
    }
    double delta_t = 0;
    if (!constraint(control, size, du, dt, a_, b_, delta_t)) {
      rep.reason = control == Control::kDisplacement
                       ? "no load level holds the controlled displacement here (the load no longer "
                         "changes it: a limit point in the displacement, or no equilibrium beyond)"
                       : "no point on the arc near the path (the arc length is too long here)";
      return rep;
    }
    a_ += delta_t * b_;
    du += a_;
    dt += delta_t;
    dn = sys_.norm(a_);
    rep.iterations = it + 1;
  }
  if (std::string inv = sys_.inverted_element(t_, u_, cand_t_, cand_u_); !inv.empty()) {
    rep.reason = "converged on a state in which " + inv;
    return rep;
  }
  // The tangent at the converged point is at hand: factorised now it gives the inertia of
  // this equilibrium exactly, and the next step's predictor.
  rep.converged = true;
  if (factorise(J_, rep)) {
    factorised_at_candidate_ = true;
    rep.negative_pivots = solver_.negative_pivots();
  }
  rep.reason.clear();
  return rep;
}

// Step sizes: halved on failure down to a floor, doubled after three easy steps up to the
// first size.
struct SizeControl {
  double size = 0, largest = 0, smallest = 0;
  int easy = 0;
  bool cut() {
    size *= 0.5;
    easy = 0;
    return std::abs(size) >= std::abs(smallest);
  }
  void grew_easily(bool easy_step) {
    if (!easy_step) {
      easy = 0;
      return;
    }
    if (++easy >= 3 && std::abs(size) < std::abs(largest)) {
      size = std::abs(2 * size) < std::abs(largest) ? 2 * size : largest;
      easy = 0;
    }
  }
};

}  // namespace

TimeLoopResult run_path_following(
    SecondOrderSystem& sys, LinearSolver& solver, const NewtonSettings& newton,
    const TimeLoopSettings& cfg, const PathSettings& path, State& s,
    const std::function<bool(const AcceptedStep&, const State&)>& observer) {
  TimeLoopResult res;
  res.t = cfg.t0;
  PathTracer tracer(sys, solver, newton, path, s, cfg.t0);
  const double span = cfg.t_end - cfg.t0;
  const double eps = 1e-9 * std::abs(cfg.step);
  auto failed = [&](std::string why) {
    res.t = tracer.t();
    res.reason = std::move(why);
    return res;
  };
  const bool by_arc = path.method == PathSettings::Method::kArcLength;
  const bool by_displacement = path.method == PathSettings::Method::kDisplacement;
  if (by_displacement && (path.equation < 0 || path.equation >= sys.global_size())) {
    return failed("displacement control: the controlled component is not free");
  }
  // Displacement control marches a pseudo-time tau over [t0, t_end].
  const double d_start = by_displacement ? sys.global_entry(s.u, path.equation) : 0;
  const double d_rate = by_displacement ? (path.displacement - d_start) / span : 0;
  double tau = cfg.t0;
  // Arc length without a given Δs: the first step is a load step of cfg.step, and Δs is
  // its length.
  const bool measure_first = by_arc && !(path.arc_length > 0);
  SizeControl ctl{.size = by_arc && !measure_first ? path.arc_length : cfg.step};
  ctl.largest = ctl.size;
  ctl.smallest = ctl.size * cfg.min_step / cfg.step;
  bool measuring = measure_first;
  auto reached_end = [&] {
    if (by_displacement) return tau >= cfg.t_end - eps;
    return std::abs(tracer.t() - cfg.t_end) <= eps;
  };
  // A start out of equilibrium (a gas chamber that starts pressurised, a state carried in) is
  // first brought to equilibrium at t0 by Newton on u alone: the path's tangent means nothing
  // off the path.
  if (tracer.in_equilibrium()) {
    // Nothing to do.
  } else if (const StepReport eq = tracer.equilibrate(); !eq.converged) {
    if (eq.interrupted) res.stopped = true;
    return failed(fmt::format(
        "at t = {:g}: path following starts from a state out of equilibrium, and Newton could "
        "not bring it to equilibrium at the start's load ({}); start from an equilibrium (a "
        "static step first)",
        cfg.t0, eq.reason));
  } else {
    s.u = tracer.u();
    res.iterations += eq.iterations;
    res.factorizations += eq.factorizations;
  }
  // Frames and history rows every output interval of travel: of the load parameter along the
  // path (which turns back through a limit point), or of the pseudo-time in displacement
  // control; and at the last step.
  double travelled = 0;
  while (!reached_end()) {
    if (by_arc && res.steps >= path.max_steps)
      return failed(fmt::format(
          "arc length: analysis.path.max_steps = {} steps taken and the path is at t = {:.6g}, "
          "not at the end t = {:.6g}; raise max_steps or give a longer arc_length",
          path.max_steps, tracer.t(), cfg.t_end));
    StepReport rep;
    double h_tau = 0;
    if (by_displacement) {
      h_tau = std::min(ctl.size, cfg.t_end - tau);
      if (h_tau >= cfg.t_end - tau - eps) h_tau = cfg.t_end - tau;
      rep = tracer.step(Control::kDisplacement, d_rate * h_tau);
    } else if (by_arc && !measuring) {
      rep = tracer.step(Control::kArcLength, ctl.size);
      // Crossing t_end: this step is replaced by one that lands on it.
      if (rep.converged && (tracer.t() - cfg.t_end) * (tracer.candidate_t() - cfg.t_end) < 0) {
        const int its = rep.iterations, facts = rep.factorizations;
        rep = tracer.step(Control::kLoad, cfg.t_end - tracer.t());
        rep.iterations += its;
        rep.factorizations += facts;
      }
    } else {
      rep = tracer.step(Control::kLoad, std::min(ctl.size, cfg.t_end - tracer.t()));
    }
    if (!rep.converged) {
      if (rep.interrupted) {
        res.stopped = true;
        return failed(fmt::format("interrupted at t = {:g}", tracer.t()));
      }
      if (!cfg.adaptive || !ctl.cut()) {
        return failed(fmt::format("at t = {:g}: {}", tracer.t(), rep.reason));
      }
      ++res.cutbacks;
      continue;
    }
    if (measuring) {
      ctl.size = ctl.largest = sys.norm(tracer.candidate_u() - tracer.u());
      ctl.smallest = ctl.size * cfg.min_step / cfg.step;
      measuring = false;
      if (!(ctl.size > 0)) {
        return failed(
            "arc length: the first load step did not move (give analysis.path.arc_length)");
      }
    }
    const double h = tracer.candidate_t() - tracer.t();
    tracer.accept();
    tau += h_tau;
    s.u = tracer.u();
    ++res.steps;
    res.iterations += rep.iterations;
    res.factorizations += rep.factorizations;
    res.t = tracer.t();
    travelled += by_displacement ? h_tau : std::abs(h);
    const bool output = cfg.output_interval <= 0 || travelled >= cfg.output_interval * (1 - 1e-9) ||
                        reached_end() || (by_arc && res.steps >= path.max_steps);
    if (output) travelled = 0;
    AcceptedStep info{.t = tracer.t(),
                      .h = h,
                      .step = res.steps,
                      .iterations = rep.iterations,
                      .total_iterations = res.iterations,
                      .factorizations = rep.factorizations,
                      .output_time = output,
                      .report = &rep};
    if (observer && !observer(info, s)) {
      res.stopped = true;
      return res;
    }
    if (cfg.adaptive) ctl.grew_easily(rep.iterations <= cfg.easy_iterations);
  }
  res.completed = true;
  return res;
}

}  // namespace velum
