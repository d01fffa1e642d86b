#include "velum/time/newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace velum {
namespace {

std::string explain_singular(const SecondOrderSystem& sys, const SparseMatrix& J) {
  std::string d = sys.diagnose_singular(J);
  return d.empty() ? "the matrix is singular or not positive definite (a mechanism, a slack or "
                     "buckled region); try a dynamic analysis, smaller steps or another "
                     "linear_solver"
                   : d;
}

// Newton on a matrix with unsupported DOFs (zero rows of stiffness and mass, made invertible
// only by load-stiffness couplings) diverges: the failure names the DOFs found at the start.
std::string with_diagnosis(std::string why, const std::string& diagnosis) {
  return diagnosis.empty() ? why : why + "; " + diagnosis;
}

// A chord step reuses the factorisation of an earlier iterate of this solve (one
// back-substitution instead of a tangent and a factorisation). It is taken when the last
// correction cut the residual by kChordGain or more: the iterates are then close enough
// that the tangent has changed little, and one that has changed more only makes the next
// correction a Newton one. With its residual evaluated first, such an iterate needs no
// tangent at all.
constexpr double kChordGain = 0.1;
// With secant updates the chord steps converge superlinearly (each pair corrects the old
// tangent along the direction just taken), so one that cuts the residual to 0.7 of the last
// is worth another: on the Hencky membrane (n = 130, static) a gain of 0.1 kept 22
// factorisations, 0.5 19 and 0.7 17; 0.9 accepted slow linear tails (the prestressed
// square's second step: 36 corrections against 8).
constexpr double kSecantGain = 0.7;
// The linear solves' forcing term: their residual against the Newton residual's (correct()).
constexpr double kForcing = 1e-3;
// Far from the solution (the residual above ten targets) a correction takes the first step
// of a mixed-precision solver unchecked, its float factor's solution, when that was last
// measured within kPassAccuracy of the right-hand side (Kelley, "Newton's method in mixed
// precision", SIAM Review 64, 2022: corrections from a low-precision factorisation keep
// Newton converging, at the rate of their relative error, while the residual is evaluated in
// double). One so taken that does not halve the residual ends that for the step: the next
// corrections are checked (and measure the solver's step again). The corrections near the
// solution are checked whatever the solver's record.
constexpr double kPassAccuracy = 1e-2;
// From the second quasi-Newton step since a factorisation on, each must also cut the
// residual to max(kSecantSlow, the first one's ratio): on a smooth problem the pairs make
// them faster as they accumulate (Hencky: 0.63, 0.54, 0.23, 0.17), where they stay slow
// they are not catching up with the tangent (a wrinkling sheet: 0.44, 0.57, 0.65, 0.67 ...),
// and a fresh one costs less than the tail (the wrinkling prestressed square, 118,803
// equations: 32 corrections without this test, 27 with it; 0.5 stopped Hencky n = 220's
// third increment at 0.54 after 0.53, one factorisation more).
constexpr double kSecantSlow = 0.6;
// Stagnation: Newton that has not halved its best residual in kStagnationWindow iterations
// is wandering, not converging (quadratic or even linear convergence halves it in a few);
// with a large max_iterations it would otherwise run on for as long as it is allowed.
constexpr int kStagnationWindow = 40;

// Energy line search along the Newton correction du from u − du (where u now is): the slope
// of the potential along du is s(α) = du · r(u − du + α du), s(0) = s0 < 0. A full step is
// kept unless it overshoots the minimum (s(1) > η |s0|, η = 1/2, as in Crisfield's method);
// then regula falsi (Illinois) finds α with |s(α)| ≤ η |s0| in a few residual evaluations
// without tangents. Moves u to the accepted point (r is its residual) and returns α. A
// stress-free membrane's first Newton step overshoots by orders of magnitude: this turns
// those 16-iteration first increments into a few.
//
// `may_extend`: du's size is not Newton's (a correction with a borrowed tension,
// SecondOrderSystem::stiffen_stress_free, which sets it) and may fall short by orders of
// magnitude: while the slope at the end still falls by more than η |s0| the step is
// lengthened kExtend-fold (at most kExtensions times), then searched as above between the
// last two ends.
double line_search(const SecondOrderSystem& sys, VecX& u, VecX& r, const VecX& du, double s0,
                   const NewtonResidual& evaluate, bool may_extend) {
  constexpr double kEta = 0.5;
  constexpr int kTrials = 8;
  constexpr double kExtend = 4;
  constexpr int kExtensions = 12;
  double sb = sys.dot(du, r);
  double a = 0, sa = s0, b = 1, alpha = 1;
  for (int k = 0; may_extend && k < kExtensions && std::isfinite(sb) && sb < kEta * s0; ++k) {
    a = b, sa = sb;
    b *= kExtend;
    u += (b - alpha) * du;
    alpha = b;
    evaluate(u, r, nullptr);
    sb = sys.dot(du, r);
  }
  if (std::isfinite(sb) && sb <= kEta * -s0) return alpha;
  int side = 1;  // which end moved last (Illinois: halve the other end's slope if it repeats)
  for (int k = 0; k < kTrials; ++k) {
    double next = std::isfinite(sb) ? b - sb * (b - a) / (sb - sa) : 0.5 * (a + b);
    next = std::clamp(next, a + 0.02 * (b - a), b - 0.02 * (b - a));
    u += (next - alpha) * du;
    alpha = next;
    evaluate(u, r, nullptr);
    const double s = sys.dot(du, r);
    if (std::isfinite(s) && std::abs(s) <= kEta * -s0) break;
    if (!std::isfinite(s) || s > 0) {
      b = alpha, sb = s;
      if (side == 1 && std::isfinite(sa)) sa *= 0.5;
      side = 1;
    } else {
      a = alpha, sa = s;
      if (side == -1 && std::isfinite(sb)) sb *= 0.5;
      side = -1;
    }
  }
  return alpha;
}

}  // namespace

bool newton_correction(SecondOrderSystem& sys, LinearSolver& solver, const SparseMatrix& J,
                       const VecX& r, VecX& x, std::string& why, double enough) {
  if (!solver.refactorize(J, sys.pattern_revision())) {
    const std::string status = solver.status();
    why = fmt::format("the {} factorisation failed{}: {}", solver.name(),
                      status.empty() ? "" : " (" + status + ")", explain_singular(sys, J));
    return false;
  }
  if (!solver.solve_within(-r, x, enough)) {
    why = fmt::format("the {} solve gave a non-finite result: {}", solver.name(),
                      explain_singular(sys, J));
    return false;
  }
  return true;
}

// One solve's state from iterate to iterate: the iterates' norms, the factorisation at hand
// and what it may still be trusted with. run() is the loop; each iterate is evaluated (and
// searched along its correction), checked for health, tested for convergence and corrected.
class NewtonSolver::Iteration {
 public:
  Iteration(NewtonSolver& n, const VecX& u_start, VecX& u, NewtonWork& w,
            const NewtonResidual& evaluate, const NewtonStart& start)
      : sys_(n.sys_),
        solver_(n.solver_),
        ns_(n.settings_),
        test_(n.settings_),
        u_start_(u_start),
        u_(u),
        r_(w.r),
        du_(w.du),
        J_(w.J),
        evaluate_(evaluate),
        search_(ns_.line_search.value_or(start.line_search_by_default)),
        carried_(start.carried && ns_.reuse_tangent),
        secant_(start.secant) {}

  StepReport run();

 private:
  // The contraction θ = ‖du_k‖/‖du_k−1‖ of the last two corrections.
  double contraction() const { return dn_prev_ > 0 ? dn_ / dn_prev_ : 1.0; }
  // The distance to the solution a converged iterate may have left.
  double allowed() const {
    return test_.distance_target(sys_.norm(u_ - u_start_),
                                 sys_.norm(u_) + sys_.reference_position_norm());
  }
  // Whether the latest residual fell by `gain_` from the one before (where the tests ask,
  // the latest is always the one in question).
  bool fell_fast() const {
    const size_t k = rep_.residuals.size() - 1;
    return rep_.residuals[k] <= gain_ * rep_.residuals[k - 1];
  }
  bool chord_solve(const VecX& b, VecX& x, double residual) {
    return pairs_ ? pairs_->solve(sys_, solver_, b, x, residual)
                  : solver_.solve_within(b, x, residual);
  }
  // The residual (with a tangent where `have_tangent` asks) at iterate `it`, after the line
  // search along the last correction; its norm recorded.
  double evaluate(int it, bool& have_tangent);
  // False (with the reason) on a diverging or stagnating residual.
  bool healthy(int it, double rn);
  // Whether iterate `it` is a solution; `chord_ready`: du_ was solved for the next
  // correction on the way.
  bool converged(int it, double rn, double target, bool& chord_ready);
  // The next correction, chord or Newton, taken; false (with the reason) when a solve fails.
  bool correct(int it, double rn, double target, bool may_chord, bool have_tangent,
               bool chord_ready);

  SecondOrderSystem& sys_;
  LowRankCorrectedSolver& solver_;
  const NewtonSettings& ns_;
  ConvergenceTest test_;
  const VecX& u_start_;
  VecX& u_;
  VecX& r_;
  VecX& du_;
  SparseMatrix& J_;
  const NewtonResidual& evaluate_;
  const bool search_;
  const bool carried_;
  SecantUpdates* const secant_;

  StepReport rep_;
  double start_ = 0, dn_ = 0, dn_prev_ = 0, s0_ = 0;
  std::string diagnosis_;
  // BFGS keeps a positive definite inverse positive definite; on an indefinite tangent (past a
  // limit point: one negative pivot on the airbag) its pairs of small or negative curvature
  // make the corrections hang on round-off (one and two processes parted within a step),
  // and an inertia that is not known (LU, a low-rank gas term) is not taken as definite.
  SecantUpdates* pairs_ = nullptr;  // `secant_` while the factorisation at hand is definite
  bool pass_trusted_ = true, last_unchecked_ = false;
  bool stiffened_ = false;  // du was solved with stiffen_stress_free's J
  int quasi_steps_ = 0;     // taken since the last factorisation
  double first_quasi_ratio_ = 0;
  double gain_ = kChordGain;  // the cut the latest residual is held to
  double best_ = std::numeric_limits<double>::infinity();
  int best_it_ = 0;
};

double NewtonSolver::Iteration::evaluate(int it, bool& have_tangent) {
  evaluate_(u_, r_, have_tangent ? &J_ : nullptr);
  // A carried factorisation whose chord step raised the residual belongs to a state too
  // far from this step's: the step starts again from its predictor, with a fresh tangent.
  if (it == 1 && carried_ && rep_.factorizations == 0 && !(sys_.norm(r_) <= rep_.residuals[0])) {
    u_ -= du_;
    evaluate_(u_, r_, &J_);
    have_tangent = true;
    dn_prev_ = 0;
    if (pairs_) pairs_->cancel();
  }
  const double alpha = it > 0 && search_ && s0_ < 0
                           ? line_search(sys_, u_, r_, du_, s0_, evaluate_, stiffened_)
                           : 1.0;
  // A cut step, or one solved with a stiffened factorisation (no tangent for chord steps,
  // whatever the search did), goes on from the tangent at the point accepted; neither says
  // anything about the contraction.
  if (alpha != 1 || stiffened_) {
    if (alpha != 1 || !have_tangent) evaluate_(u_, r_, &J_);
    have_tangent = true;
    if (pairs_) pairs_->cancel();
    dn_ *= alpha;
    dn_prev_ = 0;
  }
  if (pairs_) pairs_->close(sys_, du_, r_);  // the last correction, taken in full
  const double rn = sys_.norm(r_);
  rep_.residuals.push_back(rn);
  gain_ = pairs_ ? kSecantGain : kChordGain;
  if (pairs_ && quasi_steps_ == 1) first_quasi_ratio_ = rn / rep_.residuals[it - 1];
  if (pairs_ && quasi_steps_ >= 2)
    gain_ = std::min(gain_, std::max(kSecantSlow, first_quasi_ratio_));
  if (last_unchecked_ && !(rn <= 0.5 * rep_.residuals[it - 1])) pass_trusted_ = false;
  return rn;
}

bool NewtonSolver::Iteration::healthy(int it, double rn) {
  // Newton from a nearly stress-free state may overshoot by many orders and recover; only a
  // blow-up beyond any recovery is cut short.
  if (it >= 3 && rn > 1e30 * start_) {
    rep_.reason = with_diagnosis(
        fmt::format("Newton diverged (residual {:.3e} from {:.3e})", rn, rep_.residuals[0]),
        diagnosis_);
    return false;
  }
  if (rn < 0.5 * best_) best_ = rn, best_it_ = it;
  if (it - best_it_ >= kStagnationWindow) {
    rep_.reason = with_diagnosis(
        fmt::format("Newton stagnated: the residual has not halved in {} iterations (residual "
                    "{:.3e}, best {:.3e}); give a smaller step",
                    kStagnationWindow, rn, best_),
        diagnosis_);
    return false;
  }
  return true;
}

bool NewtonSolver::Iteration::converged(int it, double rn, double target, bool& chord_ready) {
  const bool at_floor = it > 1 && ConvergenceTest::at_floor(rn, rep_.residuals[it - 1], target);
  // Distance to the solution after the last correction: ‖du‖ θ/(1 − θ) with the observed
  // contraction θ = ‖du_k‖/‖du_k−1‖ (conservative while convergence is quadratic), so a
  // last, confirming solve is not needed once the corrections collapse.
  const double theta = contraction();
  // Slower, or not known, ‖du‖ itself; where quasi-Newton corrections may contract by as
  // little as kSecantGain (more than ‖du‖ left) it is measured instead.
  const double distance = theta < 0.5 ? dn_ * theta / (1 - theta)
                          : pairs_    ? std::numeric_limits<double>::infinity()
                                      : dn_;
  // (Not from a stiffened factorisation: the distance it measures is not J⁻¹ r.)
  if (it == 0 || stiffened_ || !(rn <= target || at_floor)) return false;
  const double limit = allowed();
  // That bound is loose while convergence is quadratic (3.8e-8 against a next correction
  // of 2.5e-11 on the Hencky membrane): before paying for a factorisation, measure the
  // distance J⁻¹ r with the one already made (a back-substitution), as accurately as the
  // corrections are computed (the forcing term: the distance to within about that
  // fraction, where a tolerance is asked of it; to round-off it took the float factor a
  // second and third pass, each with a residual in double, which the test does not need).
  if (distance > limit) chord_ready = chord_solve(-r_, du_, kForcing * rn);
  return distance <= limit || (chord_ready && sys_.norm(du_) <= limit);
}

bool NewtonSolver::Iteration::correct(int it, double rn, double target, bool may_chord,
                                      bool have_tangent, bool chord_ready) {
  // An inexact Newton correction (Dembo, Eisenstat & Steihaug 1982): a linear residual of
  // kForcing ‖r‖ keeps convergence at least that fast, and one below a tenth of the target
  // cannot keep the next residual above it. With float panels that saves refinement passes,
  // for the same corrections and answer (docs/performance.md).
  // Far from the solution, while the solver's first step has not been measured yet (the
  // first solve with a float factor), the forcing term is Eisenstat & Walker's first one,
  // 0.5 (SIAM J. Sci. Comput. 17, 1996): a stress-free sheet's first tangent is so badly
  // conditioned that the float factor's first step misses 1e-3 and its refinement stalls,
  // and the double factorisation it then falls back to (with the next one in double too)
  // buys a first correction that the line search cuts to 1.4 % anyway. Hencky n = 220: the
  // same answer, 7 → 6 factorisations in the first increment (none in double); n = 130 (its
  // first step met 1e-3 after three refinements): the same corrections.
  const double pass_accuracy = solver_.one_pass_accuracy();
  const bool far = rn > 10 * target;
  const bool unchecked = pass_trusted_ && far && pass_accuracy <= kPassAccuracy;
  const double forcing = far && std::isnan(pass_accuracy) ? 0.5 : kForcing;
  const double enough =
      unchecked ? std::numeric_limits<double>::infinity() : std::max(forcing * rn, 0.1 * target);
  const bool chord = may_chord && !have_tangent && (it == 0 || fell_fast()) &&
                     (chord_ready || chord_solve(-r_, du_, enough)) && sys_.all_finite(du_);
  stiffened_ = false;
  if (!chord) {
    if (!have_tangent) evaluate_(u_, r_, &J_);
    // From a stress-free state whose tangent is soft (a flat or shallow sheet under its
    // first load), the first correction borrows a small tension's stiffness; the line
    // search sizes it. The Hencky membrane's stress-free dome: its first step took 6
    // factorisations (the bare tangent's correction, cut to 2.5 % by the search, left a
    // state the next two corrections overshot threefold and 1.5-fold), 3 with it.
    stiffened_ = it == 0 && search_ && sys_.stiffen_stress_free(J_);
    if (!newton_correction(sys_, solver_, J_, r_, du_, rep_.reason, enough)) return false;
    ++rep_.factorizations;
    rep_.negative_pivots_seen = std::max(rep_.negative_pivots_seen, solver_.negative_pivots());
    quasi_steps_ = 0;
    pairs_ = secant_ && solver_.negative_pivots() == 0 ? secant_ : nullptr;
    if (pairs_) pairs_->clear();
  }
  if (pairs_) pairs_->open(r_);
  if (chord && pairs_) ++quasi_steps_;
  last_unchecked_ = unchecked && !chord_ready;
  s0_ = sys_.dot(du_, r_);
  u_ += du_;
  dn_prev_ = dn_;
  dn_ = sys_.norm(du_);
  rep_.iterations = it + 1;
  return true;
}

StepReport NewtonSolver::Iteration::run() {
  for (int it = 0; it <= ns_.max_iterations; ++it) {
    if (ns_.interrupt_requested()) {
      rep_.interrupted = true;
      rep_.reason = "interrupted";
      return rep_;
    }
    // When the corrections contract fast enough that this iterate should be the last
    // (quadratic model: next ≈ ‖du‖ θ²), its residual is evaluated alone first: a tangent
    // assembled at the converged point is never used.
    const double theta_now = contraction();
    const bool likely_last = it >= 2 && theta_now < 0.5 && dn_ * theta_now * theta_now <= allowed();
    const bool may_chord = ns_.reuse_tangent && (rep_.factorizations > 0 || carried_) &&
                           (it == 0 ? carried_ : it == 1 || fell_fast());
    bool have_tangent = !likely_last && !may_chord;
    const double rn = evaluate(it, have_tangent);
    if (!std::isfinite(rn)) {
      rep_.reason = fmt::format("non-finite residual at Newton iteration {}", it);
      return rep_;
    }
    if (it == 0) {
      start_ = std::max({rn, sys_.force_scale(), ns_.abs_residual});
      diagnosis_ = sys_.diagnose_singular(J_);
      if (rn <= ns_.abs_residual) {  // already in equilibrium
        rep_.converged = true;
        return rep_;
      }
    }
    if (!healthy(it, rn)) return rep_;
    // Round-off: a relative tolerance can ask for less than a ulp of the coordinates times
    // the stiffness (1.5e-8 against 1.8e-9 on the Hencky membrane). The system's estimate
    // of that level bounds the target from below.
    const double target = test_.residual_target(rn, sys_.force_scale(), sys_.residual_noise());
    bool chord_ready = false;  // du holds −J⁻¹ r (−H r) with the factorisation at hand
    if (converged(it, rn, target, chord_ready)) {
      rep_.converged = true;
      return rep_;
    }
    if (it == ns_.max_iterations) break;
    if (!correct(it, rn, target, may_chord, have_tangent, chord_ready)) return rep_;
  }
  rep_.reason = with_diagnosis(
      fmt::format("Newton did not converge in {} iterations (residual {:.3e}, reference {:.3e})",
                  ns_.max_iterations, rep_.residuals.back(), test_.reference()),
      diagnosis_);
  return rep_;
}

StepReport NewtonSolver::solve(const VecX& u_start, VecX& u, NewtonWork& work,
                               const NewtonResidual& residual, const NewtonStart& start) {
  return Iteration(*this, u_start, u, work, residual, start).run();
}

}  // namespace velum
