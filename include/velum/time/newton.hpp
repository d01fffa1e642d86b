// Newton-Raphson on r(u) = 0 for one step's unknown u, and the one convergence test every
// nonlinear solve of the time room uses (the integrators' Newton, path following's bordered
// corrector, dynamic relaxation). Residuals in the system's force units, u in its equations'.
// A failure is a status in the report, never an exception, so that the step can be cut.
#pragma once

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "velum/solve/linear_solver.hpp"
#include "velum/time/low_rank_solver.hpp"
#include "velum/time/secant_updates.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

/// Newton's iteration budget by default where a section wrinkles. A tension field's stress is
/// continuous but its tangent jumps where a point turns taut, wrinkled or slack. A sheet held
/// by a small pressure settles where its points are barely taut (strain ~ p L/(E t)), within a
/// hair of the slack kink: the tangent of one side then meets a residual whose slope on the
/// other side is far smaller, and Newton converges linearly (docs/wrinkling.md: the 15 x 15
/// slack bag going taut, 219 of 225 elements slack, contraction 0.56 per iteration whatever
/// the residual stiffness κ). A smaller step does not help (the kink stays at the solution);
/// the budget lets the linear phase reach the tolerance (log 1e-8 / log 0.56 ≈ 32).
inline constexpr int kWrinklingMaxIterations = 60;

struct NewtonSettings {
  double tolerance = 1e-8;      ///< relative, on the residual and on the increment
  double abs_residual = 1e-12;  ///< absolute floor on the residual norm
  int max_iterations = 25;
  /// Cut back corrections that overshoot the potential's minimum. Unset: on for statics, off
  /// for dynamics (the mass keeps steps short; under a follower load the slope test along
  /// the correction is no potential's, and on the C9 canopy it doubled the iterations).
  std::optional<bool> line_search;
  /// Reuse the last factorisation for the next correction while the residual falls tenfold
  /// per correction (a chord step); false: a fresh tangent at every iteration. Statics, on a
  /// factorisation known to be positive definite: the chord steps are quasi-Newton ones (its
  /// inverse with BFGS updates, SecantUpdates) and go on while each cuts the residual to 0.7
  /// (from the second on, also to max(0.6, the first one's cut)).
  bool reuse_tangent = true;
  /// Dynamics (with reuse_tangent): a step of the same size as the last starts with chord
  /// steps on the last step's factorisation, under the same tenfold test.
  bool reuse_across_steps = true;
  /// Asked between the iterations of every loop that may run long (Newton, relaxation, path
  /// steps, form-finding updates): true ends the solve at once (StepReport::interrupted). The
  /// run driver passes its signal flag here; nothing in the time room sees the driver.
  std::function<bool()> interrupted;
  bool interrupt_requested() const { return interrupted && interrupted(); }
};

struct StepReport {
  bool converged = false;
  int iterations = 0;             ///< corrections (Newton and chord steps)
  int factorizations = 0;         ///< of which with a fresh tangent
  std::vector<double> residuals;  ///< residual norm at each iteration (before its solve)
  std::string reason;             ///< why it failed
  /// Ended by NewtonSettings::interrupted (a signal): the run stops, no cut-back.
  bool interrupted = false;
  /// A smaller step cannot help (a per-level budget spent): the run ends with `reason`.
  bool ends_run = false;
  /// Negative eigenvalues seen in any factorisation of this solve (-1: none told), for the
  /// diagnosis of a failed static step: past a limit point the tangent turns indefinite.
  int negative_pivots_seen = -1;
  /// Static steps: negative eigenvalues of the tangent stiffness at the converged state (0: a
  /// stable equilibrium); -1 when the factorisation does not tell (LU) or not static.
  int negative_pivots = -1;
  /// Static load steps: from a stable equilibrium to a stable one through an indefinite
  /// tangent, with an increment far beyond the last one's: likely a jump over a limit point.
  bool branch_jump = false;
};

/// When an iterate is a solution: its residual within the tolerance of the largest force
/// seen in the solve (never below the absolute floor or the residual's round-off level), and
/// the distance to the solution it may have left within the tolerance of the step's change
/// (never below the round-off of the position).
class ConvergenceTest {
 public:
  ConvergenceTest(double tolerance, double abs_residual)
      : tolerance_(tolerance), abs_residual_(abs_residual) {}
  explicit ConvergenceTest(const NewtonSettings& s)
      : ConvergenceTest(s.tolerance, s.abs_residual) {}

  /// Takes the residual norm rn of an iterate, with the system's force scale and round-off
  /// level there, into the solve's reference force (the largest seen since construction or
  /// restart()) and returns the residual target against it.
  double residual_target(double rn, double force_scale, double noise) {
    reference_ = std::max({reference_, rn, force_scale});
    return target_against(reference_, noise);
  }
  /// The residual target against a force scale given by the caller (no reference kept).
  double target_against(double scale, double noise) const {
    return std::max({tolerance_ * scale, abs_residual_, noise});
  }
  /// The distance to the solution an iterate may leave: `change` the norm of the step's
  /// change of u so far, `position` the norm of the positions (u and the reference positions
  /// it moves, SecondOrderSystem::reference_position_norm).
  double distance_target(double change, double position) const {
    return std::max(tolerance_ * change, 1e-14 * (1 + position));
  }
  /// A residual that has stopped falling (less than halved from the last, `previous`) within
  /// 1000 times the target: the round-off floor where the system gives no level, which meets
  /// the residual part of the test as a residual within the target does.
  static bool at_floor(double rn, double previous, double target) {
    return rn >= 0.5 * previous && rn <= 1e3 * target;
  }
  /// Both parts of the test: the residual norm within `target` and the distance to the
  /// solution within `allowed` (distance_target).
  static bool met(double rn, double target, double distance, double allowed) {
    return rn <= target && distance <= allowed;
  }
  double reference() const { return reference_; }
  void restart() { reference_ = 0; }

 private:
  double tolerance_, abs_residual_;
  double reference_ = 0;
};

/// The residual r(u) (and, when J != null, its Jacobian, pattern fixed) of the step's
/// unknown; its low-rank part is the system's (SecondOrderSystem::jacobian_low_rank).
using NewtonResidual = std::function<void(const VecX& u, VecX& r, SparseMatrix* J)>;

/// How one Newton solve starts, beyond its settings.
struct NewtonStart {
  /// The line search where NewtonSettings::line_search is unset (the integrator's default).
  bool line_search_by_default = false;
  /// The solver holds the factorisation of an earlier step's Jacobian with the same shift
  /// coefficients (dynamics, same step size): the first correction is then a chord step with
  /// it, and the chord steps go on under the same test as within a step; the first that does
  /// not cut the residual tenfold is followed by a fresh tangent at once.
  bool carried = false;
  /// Statics: on a factorisation known to be positive definite the chord steps are
  /// quasi-Newton ones, its inverse updated by the corrections taken since it was made (BFGS),
  /// going on while each cuts the residual to 0.7 of the last. Null: plain chord steps.
  SecantUpdates* secant = nullptr;
};

/// The vectors and the matrix of a solve, kept by the caller between solves (the matrix's
/// pattern is allocated once; after a solve J is the last tangent assembled, r the residual
/// at u and du the last correction).
struct NewtonWork {
  VecX r, du;
  SparseMatrix J;
};

/// Newton-Raphson with an energy line search, chord (and quasi-Newton) steps, inexact
/// corrections and the convergence test above, every solve through the low-rank-aware
/// solver (an enclosed gas's p(V) coupling applied on the sparse factorisation).
class NewtonSolver {
 public:
  NewtonSolver(SecondOrderSystem& sys, LowRankCorrectedSolver& solver,
               const NewtonSettings& settings)
      : sys_(sys), solver_(solver), settings_(settings) {}

  /// Solves from the predictor u (u_start: where the step started, for the increment test),
  /// moving u to the solution; on failure the report says why and u is the last iterate.
  StepReport solve(const VecX& u_start, VecX& u, NewtonWork& work, const NewtonResidual& residual,
                   const NewtonStart& start = {});

 private:
  class Iteration;

  SecondOrderSystem& sys_;
  LowRankCorrectedSolver& solver_;
  const NewtonSettings& settings_;
};

/// Factorises J and solves J x = −r, to within ‖J x + r‖₂ <= enough where the solver can stop
/// early (0: as accurately as it solves); says why in `why` on failure.
bool newton_correction(SecondOrderSystem& sys, LinearSolver& solver, const SparseMatrix& J,
                       const VecX& r, VecX& x, std::string& why, double enough = 0);

}  // namespace velum
