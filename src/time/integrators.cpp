#include "velum/time/integrators.hpp"

#include <fmt/format.h>

#include <cmath>

namespace velum {
namespace {

// Factorises J and solves J x = −r; fills `why` on failure.
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

bool newton_solve(SecondOrderSystem& sys, LinearSolver& solver, const SparseMatrix& J,
                  const VecX& r, VecX& x, std::string& why) {
  if (!solver.refactorize(J)) {
    const std::string status = solver.status();
    why = fmt::format("the {} factorisation failed{}: {}", solver.name(),
                      status.empty() ? "" : " (" + status + ")", explain_singular(sys, J));
    return false;
  }
  if (!solver.solve(-r, x)) {
    why = fmt::format("the {} solve gave a non-finite result: {}", solver.name(),
                      explain_singular(sys, J));
    return false;
  }
  return true;
}

bool residual_converged(double rnorm, double ref, const NewtonSettings& ns) {
  return rnorm <= std::max(ns.tolerance * ref, ns.abs_residual);
}

// Full Newton-Raphson on the unknown u, starting from its predictor: `evaluate(u, r, J)` gives
// the residual and the (shifted) Jacobian there. Converged when the residual is below the
// tolerance relative to the largest force seen and the last correction is below the tolerance
// relative to the step's change u − u_start. Stops early on a non-finite or diverging residual.
template <class Evaluate>
StepReport newton_iterate(SecondOrderSystem& sys, LinearSolver& solver, const NewtonSettings& ns,
                          const VecX& u_start, VecX& u, VecX& r, VecX& du, SparseMatrix& J,
                          const Evaluate& evaluate) {
  StepReport rep;
  double ref = 0, start = 0;
  std::string diagnosis;
  for (int it = 0; it <= ns.max_iterations; ++it) {
    evaluate(u, r, J);
    const double rn = r.norm();
    rep.residuals.push_back(rn);
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
    ref = std::max({ref, rn, sys.force_scale()});
    // Round-off floor: once the correction is converged, a residual that has stopped
    // falling (less than halved) within 1000 times the target is as small as the arithmetic
    // allows (seen at 1.5 times the target after a good predictor, on 36,800 DOFs).
    const bool at_floor = it > 1 && rn >= 0.5 * rep.residuals[it - 1] &&
                          rn <= 1e3 * std::max(ns.tolerance * ref, ns.abs_residual);
    if (it > 0 && (residual_converged(rn, ref, ns) || at_floor) &&
        du.norm() <= std::max(ns.tolerance * (u - u_start).norm(), 1e-14 * (1 + u.norm()))) {
      rep.converged = true;
      rep.iterations = it;
      return rep;
    }
    if (it == ns.max_iterations) break;
    if (!newton_solve(sys, solver, J, r, du, rep.reason)) return rep;
    u += du;
    rep.iterations = it + 1;
  }
  rep.reason = with_diagnosis(
      fmt::format("Newton did not converge in {} iterations (residual {:.3e}, reference {:.3e})",
                  ns.max_iterations, rep.residuals.back(), ref),
      diagnosis);
  return rep;
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
  const double cu = 1 - alpha_f;
  const double cv = (1 - alpha_f) * gamma / (beta * h);
  const double ca = (1 - alpha_m) / (beta * h * h);
  VecX a(un_.size()), v(un_.size());
  auto kinematics = [&](const VecX& u) {
    a = (u - un_ - h * vn_ - (0.5 - beta) * h * h * an_) / (beta * h * h);
    v = vn_ + h * ((1 - gamma) * an_ + gamma * a);
  };
  // Predictor: constant acceleration.
  VecX u = un_ + h * vn_ + 0.5 * h * h * an_;
  const StepReport rep = newton_iterate(sys, solver, newton, un_, u, r_, du_, J_,
                                        [&](const VecX& x, VecX& r, SparseMatrix& J) {
                                          kinematics(x);
                                          uf_ = (1 - alpha_f) * x + alpha_f * un_;
                                          vf_ = (1 - alpha_f) * v + alpha_f * vn_;
                                          am_ = (1 - alpha_m) * a + alpha_m * an_;
                                          sys.evaluate(tf, uf_, vf_, am_, cu, cv, ca, r, &J);
                                        });
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
  rep.converged = s.a.allFinite();
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
  if (!a.allFinite()) {
    rep.reason = "non-finite acceleration (step above the stable limit?)";
    return rep;
  }
  s.u = u;
  s.v = vhalf + 0.5 * h * a;
  s.a = a;
  rep.converged = true;
  return rep;
}

StepReport StaticNewton::step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                              State& s) {
  zero_.setZero(sys.size());
  auto solve_from = [&](VecX& u) {
    return newton_iterate(sys, solver, newton, s.u, u, r_, du_, J_,
                          [&](const VecX& x, VecX& r, SparseMatrix& J) {
                            sys.evaluate(t + h, x, zero_, zero_, 1.0, 0.0, 0.0, r, &J);
                          });
  };
  // Extrapolate only along an increment that ended where this step starts (not after a
  // restart or a change of state from outside).
  const bool extrapolate = h_prev_ > 0 && std::abs(t - t_prev_) <= 1e-12 * (1 + std::abs(t)) &&
                           u_prev_.size() == s.u.size();
  VecX u = s.u;
  if (extrapolate) u += (h / h_prev_) * (s.u - u_prev_);
  StepReport rep = solve_from(u);
  if (!rep.converged && extrapolate) {
    const int spent = rep.iterations;
    u = s.u;
    rep = solve_from(u);
    rep.iterations += spent;
  }
  if (rep.converged) {
    u_prev_ = s.u;
    h_prev_ = h;
    t_prev_ = t + h;
    s.u = u;
  }
  return rep;
}

double stable_time_step(SecondOrderSystem& sys, double t, const State& s) {
  VecX r, zero = VecX::Zero(sys.size());
  SparseMatrix K;
  sys.evaluate(t, s.u, s.v, zero, 1.0, 0.0, 0.0, r, &K);
  const VecX& m = sys.lumped_mass();
  VecX x = VecX::Ones(sys.size());
  double lambda = 0;
  for (int it = 0; it < 50; ++it) {
    const VecX y = (K * x).cwiseQuotient(m);
    const double l = y.norm() / x.norm();
    x = y / y.norm();
    if (std::abs(l - lambda) < 1e-4 * l) {
      lambda = l;
      break;
    }
    lambda = l;
  }
  return lambda > 0 ? 2.0 / std::sqrt(lambda) : INFINITY;
}

}  // namespace velum
