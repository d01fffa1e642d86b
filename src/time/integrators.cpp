#include "velum/time/integrators.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "velum/time/low_rank_solver.hpp"
#include "velum/time/secant_updates.hpp"

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

// Factorises J and solves J x = −r, to within ‖J x + r‖₂ <= enough where the solver can stop
// early (0: as accurately as it solves); fills `why` on failure.
bool newton_solve(SecondOrderSystem& sys, LinearSolver& solver, const SparseMatrix& J,
                  const VecX& r, VecX& x, std::string& why, double enough = 0) {
  if (!solver.refactorize(J)) {
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
template <class Evaluate>
double line_search(const SecondOrderSystem& sys, VecX& u, VecX& r, const VecX& du, double s0,
                   const Evaluate& evaluate, bool may_extend) {
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

// Newton-Raphson on the unknown u, starting from its predictor: `evaluate(u, r, J)` gives the
// residual and the (shifted) Jacobian there; with ns.reuse_tangent, chord steps once the
// residual falls fast (below). Converged when the residual is below the tolerance relative to
// the largest force seen (or below its round-off level) and the estimated distance to the
// solution is below the tolerance relative to the step's change u − u_start. Stops early on
// a non-finite or diverging residual.
//
// `carried`: `solver` holds the factorisation of an earlier step's Jacobian with the same
// shift coefficients (dynamics, same step size): the first correction is then a chord step
// with it, and the chord steps go on under the same test as within a step; the first that
// does not cut the residual tenfold is followed by a fresh tangent at once.
//
// `secant` (statics): on a factorisation known to be positive definite, the chord steps are
// quasi-Newton ones, its inverse updated by the corrections taken since it was made (BFGS),
// and go on while each cuts the residual to kSecantGain of the last.
template <class Evaluate>
StepReport newton_iterate(SecondOrderSystem& sys, LowRankCorrectedSolver& solver,
                          const NewtonSettings& ns, bool search_by_default, bool carried,
                          SecantUpdates* secant, const VecX& u_start, VecX& u, VecX& r, VecX& du,
                          SparseMatrix& J, const Evaluate& evaluate) {
  const bool search = ns.line_search.value_or(search_by_default);
  StepReport rep;
  double ref = 0, start = 0, dn = 0, dn_prev = 0, s0 = 0;
  std::string diagnosis;
  // The contraction θ = ‖du_k‖/‖du_k−1‖ of the last two corrections, and the distance to the
  // solution a converged iterate may have left.
  auto contraction = [&] { return dn_prev > 0 ? dn / dn_prev : 1.0; };
  auto allowed = [&] {
    return std::max(ns.tolerance * sys.norm(u - u_start), 1e-14 * (1 + sys.norm(u)));
  };
  // A chord step reuses the factorisation of an earlier iterate of this solve (one
  // back-substitution instead of a tangent and a factorisation). It is taken when the last
  // correction cut the residual by kChordGain or more: the iterates are then close enough
  // that the tangent has changed little, and one that has changed more only makes the next
  // correction a Newton one. With its residual evaluated first, such an iterate needs no
  // tangent at all.
  constexpr double kChordGain = 0.1;
  // With secant updates the chord steps converge superlinearly (each pair corrects the old
  // tangent along the direction just taken), so one that cuts the residual to 0.7 of the last
  // is worth another: on a smooth static problem a stricter gain keeps more factorisations,
  // and a looser one (0.9) accepts slow linear tails that take many more corrections than a
  // fresh tangent would (docs/performance.md).
  constexpr double kSecantGain = 0.7;
  // BFGS keeps a positive definite inverse positive definite; on an indefinite tangent (past a
  // limit point: one negative pivot on the airbag) its pairs of small or negative curvature
  // make the corrections hang on round-off (one and two processes parted within a step),
  // and an inertia that is not known (LU, a low-rank gas term) is not taken as definite.
  SecantUpdates* pairs = nullptr;  // `secant` while the factorisation at hand is definite
  auto chord_solve = [&](const VecX& b, VecX& x, double residual) {
    return pairs ? pairs->solve(sys, solver, b, x, residual) : solver.solve_within(b, x, residual);
  };
  // The linear solves' forcing term: their residual against the Newton residual's (below).
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
  bool pass_trusted = true, last_unchecked = false;
  // From the second quasi-Newton step since a factorisation on, each must also cut the
  // residual to max(kSecantSlow, the first one's ratio): on a smooth problem the pairs make
  // them faster as they accumulate (Hencky: 0.63, 0.54, 0.23, 0.17), where they stay slow
  // they are not catching up with the tangent (a wrinkling sheet: 0.44, 0.57, 0.65, 0.67 ...),
  // and a fresh one costs less than the tail (on the wrinkling prestressed square, fewer
  // corrections and less time than without this test; 0.5 stops smooth runs of ratios that
  // hover just above it, for a factorisation more).
  constexpr double kSecantSlow = 0.6;
  bool stiffened = false;  // du was solved with stiffen_stress_free's J
  int quasi_steps = 0;     // taken since the last factorisation
  double first_quasi_ratio = 0;
  double gain = kChordGain;  // the cut the latest residual is held to
  // Whether the latest residual fell by `gain` from the one before (where the tests below ask,
  // the latest is always the one in question).
  auto fell_fast = [&] {
    const size_t k = rep.residuals.size() - 1;
    return rep.residuals[k] <= gain * rep.residuals[k - 1];
  };
  // Stagnation: Newton that has not halved its best residual in kStagnationWindow iterations
  // is wandering, not converging (quadratic or even linear convergence halves it in a few);
  // with a large max_iterations it would otherwise run on for as long as it is allowed.
  constexpr int kStagnationWindow = 40;
  double best = std::numeric_limits<double>::infinity();
  int best_it = 0;
  carried = carried && ns.reuse_tangent;
  for (int it = 0; it <= ns.max_iterations; ++it) {
    // When the corrections contract fast enough that this iterate should be the last
    // (quadratic model: next ≈ ‖du‖ θ²), its residual is evaluated alone first: a tangent
    // assembled at the converged point is never used.
    const double theta_now = contraction();
    const bool likely_last = it >= 2 && theta_now < 0.5 && dn * theta_now * theta_now <= allowed();
    const bool may_chord = ns.reuse_tangent && (rep.factorizations > 0 || carried) &&
                           (it == 0 ? carried : it == 1 || fell_fast());
    bool have_tangent = !likely_last && !may_chord;
    evaluate(u, r, have_tangent ? &J : nullptr);
    // A carried factorisation whose chord step raised the residual belongs to a state too
    // far from this step's: the step starts again from its predictor, with a fresh tangent.
    if (it == 1 && carried && rep.factorizations == 0 && !(sys.norm(r) <= rep.residuals[0])) {
      u -= du;
      evaluate(u, r, &J);
      have_tangent = true;
      dn_prev = 0;
      if (pairs) pairs->cancel();
    }
    const double alpha =
        it > 0 && search && s0 < 0 ? line_search(sys, u, r, du, s0, evaluate, stiffened) : 1.0;
    // A cut step, or one solved with a stiffened factorisation (no tangent for chord steps,
    // whatever the search did), goes on from the tangent at the point accepted; neither says
    // anything about the contraction.
    if (alpha != 1 || stiffened) {
      if (alpha != 1 || !have_tangent) evaluate(u, r, &J);
      have_tangent = true;
      if (pairs) pairs->cancel();
      dn *= alpha;
      dn_prev = 0;
    }
    if (pairs) pairs->close(sys, du, r);  // the last correction, taken in full
    const double rn = sys.norm(r);
    rep.residuals.push_back(rn);
    gain = pairs ? kSecantGain : kChordGain;
    if (pairs && quasi_steps == 1) first_quasi_ratio = rn / rep.residuals[it - 1];
    if (pairs && quasi_steps >= 2) gain = std::min(gain, std::max(kSecantSlow, first_quasi_ratio));
    if (last_unchecked && !(rn <= 0.5 * rep.residuals[it - 1])) pass_trusted = false;
    if (!std::isfinite(rn)) {
      rep.reason = fmt::format("non-finite residual at Newton iteration {}", it);
      return rep;
    }
    if (it == 0) {
      start = std::max({rn, sys.force_scale(), ns.abs_residual});
      diagnosis = sys.diagnose_singular(J);
      if (rn <= ns.abs_residual) {  // already in equilibrium
        rep.converged = true;
        return rep;
      }
    }
    // Newton from a nearly stress-free state may overshoot by many orders and recover; only a
    // blow-up beyond any recovery is cut short.
    if (it >= 3 && rn > 1e30 * start) {
      rep.reason = with_diagnosis(
          fmt::format("Newton diverged (residual {:.3e} from {:.3e})", rn, rep.residuals[0]),
          diagnosis);
      return rep;
    }
    if (rn < 0.5 * best) best = rn, best_it = it;
    if (it - best_it >= kStagnationWindow) {
      rep.reason = with_diagnosis(
          fmt::format("Newton stagnated: the residual has not halved in {} iterations (residual "
                      "{:.3e}, best {:.3e}); give a smaller step",
                      kStagnationWindow, rn, best),
          diagnosis);
      return rep;
    }
    ref = std::max({ref, rn, sys.force_scale()});
    // Round-off: a relative tolerance can ask for less than a ulp of the coordinates times
    // the stiffness (1.5e-8 against 1.8e-9 on the Hencky membrane). The system's estimate
    // of that level bounds the target from below; a residual that has stopped falling (less
    // than halved) within 1000 times the target is taken as the floor when there is none.
    const double target = std::max({ns.tolerance * ref, ns.abs_residual, sys.residual_noise()});
    const bool at_floor = it > 1 && rn >= 0.5 * rep.residuals[it - 1] && rn <= 1e3 * target;
    // Distance to the solution after the last correction: ‖du‖ θ/(1 − θ) with the observed
    // contraction θ = ‖du_k‖/‖du_k−1‖ (conservative while convergence is quadratic), so a
    // last, confirming solve is not needed once the corrections collapse.
    const double theta = contraction();
    // Slower, or not known, ‖du‖ itself; where quasi-Newton corrections may contract by as
    // little as kSecantGain (more than ‖du‖ left) it is measured instead.
    const double distance = theta < 0.5 ? dn * theta / (1 - theta)
                            : pairs     ? std::numeric_limits<double>::infinity()
                                        : dn;
    bool chord_ready = false;  // du holds −J⁻¹ r (−H r) with the factorisation at hand
    // (Not from a stiffened factorisation: the distance it measures is not J⁻¹ r.)
    if (it > 0 && !stiffened && (rn <= target || at_floor)) {
      const double limit = allowed();
      // That bound is loose while convergence is quadratic (3.8e-8 against a next correction
      // of 2.5e-11 on the Hencky membrane): before paying for a factorisation, measure the
      // distance J⁻¹ r with the one already made (a back-substitution), as accurately as the
      // corrections are computed (the forcing term below: the distance to within about that
      // fraction, where a tolerance is asked of it; to round-off it took the float factor a
      // second and third pass, each with a residual in double, which the test does not need).
      if (distance > limit) chord_ready = chord_solve(-r, du, kForcing * rn);
      if (distance <= limit || (chord_ready && sys.norm(du) <= limit)) {
        rep.converged = true;
        return rep;
      }
    }
    if (it == ns.max_iterations) break;
    // An inexact Newton correction (Dembo, Eisenstat & Steihaug 1982): a linear residual of
    // kForcing ‖r‖ keeps convergence at least that fast, and one below a tenth of the target
    // cannot keep the next residual above it. With float panels that saves refinement passes,
    // for the same corrections and answer (docs/performance.md).
    // Far from the solution, while the solver's first step has not been measured yet (the
    // first solve with a float factor), the forcing term is Eisenstat & Walker's first one,
    // 0.5 (SIAM J. Sci. Comput. 17, 1996): a stress-free sheet's first tangent is so badly
    // conditioned that the float factor's first step misses 1e-3 and its refinement stalls,
    // and the double factorisation it then falls back to (with the next one in double too)
    // buys a first correction that the line search cuts to 1.4 % anyway. On a large stress-free
    // dome this keeps the first increment in float, a factorisation shorter, for the same answer
    // (docs/performance.md).
    const double pass_accuracy = solver.one_pass_accuracy();
    const bool far = rn > 10 * target;
    const bool unchecked = pass_trusted && far && pass_accuracy <= kPassAccuracy;
    const double forcing = far && std::isnan(pass_accuracy) ? 0.5 : kForcing;
    const double enough =
        unchecked ? std::numeric_limits<double>::infinity() : std::max(forcing * rn, 0.1 * target);
    const bool chord = may_chord && !have_tangent && (it == 0 || fell_fast()) &&
                       (chord_ready || chord_solve(-r, du, enough)) && sys.all_finite(du);
    stiffened = false;
    if (!chord) {
      if (!have_tangent) evaluate(u, r, &J);
      // From a stress-free state whose tangent is soft (a flat or shallow sheet under its
      // first load), the first correction borrows a small tension's stiffness; the line
      // search sizes it. From a stress-free dome the bare tangent's correction, cut short by the
      // search, left a state the next corrections overshot; with the borrowed tension the first
      // step takes about half the factorisations (docs/performance.md).
      stiffened = it == 0 && search && sys.stiffen_stress_free(J);
      if (!newton_solve(sys, solver, J, r, du, rep.reason, enough)) return rep;
      ++rep.factorizations;
      quasi_steps = 0;
      pairs = secant && solver.negative_pivots() == 0 ? secant : nullptr;
      if (pairs) pairs->clear();
    }
    if (pairs) pairs->open(r);
    if (chord && pairs) ++quasi_steps;
    last_unchecked = unchecked && !chord_ready;
    s0 = sys.dot(du, r);
    u += du;
    dn_prev = dn;
    dn = sys.norm(du);
    rep.iterations = it + 1;
  }
  rep.reason = with_diagnosis(
      fmt::format("Newton did not converge in {} iterations (residual {:.3e}, reference {:.3e})",
                  ns.max_iterations, rep.residuals.back(), ref),
      diagnosis);
  return rep;
}

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
  SparseMatrix J;
  VecX r, zero = VecX::Zero(sys.size()), da;
  sys.evaluate(t, s.u, s.v, zero, 0.0, 0.0, 1.0, r, &J);
  if (!newton_solve(sys, solver, J, r, da, rep.reason)) {
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
                       carried_shift_ == Vec3(cu, cv, ca) && J_.rows() == un_.size() &&
                       last_factorizations_ <= 1;
  StepReport rep = newton_iterate(sys, *low_rank_, newton, false, carried, nullptr, un_, u, r_, du_,
                                  J_, [&](const VecX& x, VecX& r, SparseMatrix* J) {
                                    kinematics(x);
                                    uf_ = (1 - alpha_f) * x + alpha_f * un_;
                                    vf_ = (1 - alpha_f) * v + alpha_f * vn_;
                                    am_ = (1 - alpha_m) * a + alpha_m * an_;
                                    sys.evaluate(tf, uf_, vf_, am_, cu, cv, ca, r, J);
                                  });
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
  StepReport rep;
  const VecX vhalf = s.v + 0.5 * h * s.a;
  const VecX u = s.u + h * vhalf;
  zero_.setZero(sys.size());
  sys.evaluate(t + h, u, vhalf, zero_, 0, 0, 0, r_, nullptr);
  const VecX a = -r_.cwiseQuotient(sys.lumped_mass());
  if (!sys.all_finite(a)) {
    rep.reason = "non-finite acceleration (step above the stable limit?)";
    return rep;
  }
  s.u = u;
  s.v = vhalf + 0.5 * h * a;
  s.a = a;
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
  rep.negative_pivots = solver.negative_pivots();
  // The count is that of the last tangent factorised, at an iterate near u; where it differs
  // from the last step's (a critical point may lie between), it is made exact at u itself,
  // as it is where this step factorised nothing (it started in equilibrium).
  const bool changed = rep.negative_pivots >= 0 && rep.negative_pivots != negative_pivots_;
  if (rep.factorizations > 0 && !changed) return;
  sys.evaluate(t, u, zero_, zero_, 1.0, 0.0, 0.0, r_, &J_);
  ++rep.factorizations;
  rep.negative_pivots = solver.refactorize(J_) ? solver.negative_pivots() : -1;
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
    by_line.setZero(J_.rows());
    by_parabola.setZero(J_.rows());
    const int* outer = J_.outerIndexPtr();
    const int* inner = J_.innerIndexPtr();
    const double* value = J_.valuePtr();
    for (int j = 0; j < J_.outerSize(); ++j) {
      const double a = linear_[j], b = parabolic_[j];
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        by_line[inner[k]] += value[k] * a;
        by_parabola[inner[k]] += value[k] * b;
      }
    }
    sys.complete(by_line);  // J_ may be this process's share
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
    StepReport rep = newton_iterate(sys, low_rank, newton, true, false,
                                    newton.reuse_tangent ? &secant_ : nullptr, s.u, u, r_, du_, J_,
                                    [&](const VecX& x, VecX& r, SparseMatrix* J) {
                                      sys.evaluate(t + h, x, zero_, zero_, 1.0, 0.0, 0.0, r, J);
                                    });
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
  if (extrapolated && (!rep.converged || less_stable)) {
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
  }
  if (rep.converged) {
    remember(sys, t, h, s.u, u, rep);
    s.u = u;
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

double stable_time_step(SecondOrderSystem& sys, double t, const State& s) {
  VecX r, zero = VecX::Zero(sys.size());
  SparseMatrix K;
  sys.evaluate(t, s.u, s.v, zero, 1.0, 0.0, 0.0, r, &K);
  const VecX& m = sys.lumped_mass();
  VecX x = VecX::Ones(sys.size());
  double lambda = 0;
  for (int it = 0; it < 50; ++it) {
    VecX Kx = K * x;
    sys.complete(Kx);  // K may be this process's share
    const VecX y = Kx.cwiseQuotient(m);
    const double l = sys.norm(y) / sys.norm(x);
    x = y / sys.norm(y);
    if (std::abs(l - lambda) < 1e-4 * l) {
      lambda = l;
      break;
    }
    lambda = l;
  }
  return lambda > 0 ? 2.0 / std::sqrt(lambda) : INFINITY;
}

}  // namespace velum
