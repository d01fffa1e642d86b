// The prestress and tension-field wrappers of a general sheet law (sheet_law_wrappers.hpp).
// The tension field: with t = (−sin θ, cos θ), v_t = t⊗t and v_nt = sym(n⊗t) in engineering
// Voigt form (as in tension_field.cpp), the wrinkled point is evaluated at the elastic strain
// E_e = E − β v_t and the two conditions R = [v_t·S(E_e), v_nt·S(E_e)] = 0 fix (β, θ). With
// v_t' = −2 v_nt, v_nt' = v_t − v_n and C_e = C(E_e):
//   ∂R/∂β = −[v_tᵀC_e v_t, v_ntᵀC_e v_t],
//   ∂R/∂θ = [−2 v_nt·S + 2β v_tᵀC_e v_nt, (v_t − v_n)·S + 2β v_ntᵀC_e v_nt],
// the Jacobian of Newton's iteration and, at the root, of the implicit differentiation that
// gives the tangent (the linear law's formula with Q replaced by C_e).
#include "velum/material/sheet_law_wrappers.hpp"

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "velum/material/linear_sheet_law.hpp"
#include "velum/material/plane_stress.hpp"

namespace velum {
namespace {

struct Frame {
  Vec3 vt, vnt, vn;
  explicit Frame(double theta) {
    const double c = std::cos(theta), s = std::sin(theta);
    vt = {s * s, c * c, -2 * s * c};
    vnt = {-c * s, s * c, c * c - s * s};
    vn = {c * c, s * s, 2 * c * s};
  }
};

double min_principal(const Vec3& S) {
  const double mean = 0.5 * (S[0] + S[1]), half = 0.5 * (S[0] - S[1]);
  return mean - std::sqrt(half * half + S[2] * S[2]);
}

/// Angle of the major principal direction of a symmetric tensor [a11, a22, a12].
double major_angle(const Vec3& a) {
  return 0.5 * std::atan2(2 * a[2], a[0] - a[1]);
}

}  // namespace

PrestressedSheetLaw::PrestressedSheetLaw(std::unique_ptr<SheetLawBase> law, const Vec3& S0)
    : law_(std::move(law)), S0_(S0) {
  if (!law_) throw std::invalid_argument("a prestressed sheet law needs a law");
}

void PrestressedSheetLaw::evaluate(const Vec3& E, std::span<const double> h,
                                   SheetResponse& out) const {
  law_->evaluate(E, h, out);
  out.S += S0_;
}

double PrestressedSheetLaw::energy(const Vec3& E, std::span<const double> h) const {
  return law_->energy(E, h) + S0_.dot(E);
}

TensionFieldSheetLaw::TensionFieldSheetLaw(std::unique_ptr<SheetLawBase> law, double kappa)
    : law_(std::move(law)), kappa_(kappa) {
  if (!law_) throw std::invalid_argument("a wrinkling sheet law needs a law");
  if (!(kappa >= 0 && kappa < 1))
    throw MaterialError("the residual stiffness of a wrinkling sheet must lie in [0, 1)");
  const Vec3 S0 = law_->prestress();
  const Mat3 Qplus = law_->reference_stiffness().completeOrthogonalDecomposition().pseudoInverse();
  slack_energy_ = -0.5 * S0.dot(Qplus * S0);
}

TensionFieldSheetLaw::Solution TensionFieldSheetLaw::solve(const Vec3& E, std::span<const double> h,
                                                           SheetResponse& out) const {
  Solution sol;
  SheetResponse r;
  law_->evaluate(E, h, r);
  if (!(min_principal(r.S) < 0)) {  // taut (or not a number: passed on as it is)
    out = r;
    out.state = WrinkleState::kTaut;
    out.angle = 0;
    return sol;
  }
  const double scale =
      std::max(r.C.cwiseAbs().maxCoeff(), reference_stiffness().cwiseAbs().maxCoeff());

  // Newton on (β, θ) from a guess; true when it converged to an admissible root.
  SheetResponse re;
  // A step that raises |R| is halved (up to ten times): a law that stiffens or yields along t
  // (plasticity) would otherwise make the full steps swing about the root.
  auto newton = [&](double beta, double theta, double& beta_out, double& theta_out) {
    double last = std::numeric_limits<double>::infinity(), alpha = 1;
    Vec2 d = Vec2::Zero();
    for (int it = 0; it < 100; ++it) {
      const Frame f(theta);
      law_->evaluate(E - beta * f.vt, h, re);
      const Vec2 R(f.vt.dot(re.S), f.vnt.dot(re.S));
      if (!re.S.allFinite() || R.norm() > last) {
        if (it == 0 || alpha < 1e-3) return false;
        beta -= alpha * d[0];  // back to the last point, then half the step
        theta -= alpha * d[1];
        alpha *= 0.5;
        beta += alpha * d[0];
        theta += alpha * d[1];
        continue;
      }
      last = R.norm();
      const Vec3 Cvt = re.C * f.vt, Cvnt = re.C * f.vnt;
      Mat2 J;
      J << -f.vt.dot(Cvt), -2 * f.vnt.dot(re.S) + 2 * beta * f.vt.dot(Cvnt), -f.vnt.dot(Cvt),
          (f.vt - f.vn).dot(re.S) + 2 * beta * f.vnt.dot(Cvnt);
      const double stress = std::max(std::abs(f.vn.dot(re.S)), 1e-14 * scale);
      if (R.norm() <= 1e-13 * stress) {
        beta_out = beta;
        theta_out = theta;
        return beta <= 1e-12 && f.vn.dot(re.S) > 0;
      }
      const double det = J.determinant();
      if (!(std::abs(det) > 0)) return false;
      d = -J.inverse() * R;
      if (std::abs(d[1]) > 0.25) d *= 0.25 / std::abs(d[1]);
      alpha = 1;
      beta += d[0];
      theta += d[1];
      if (std::abs(d[0]) < 1e-13 * (std::abs(beta) + 1e-3) && std::abs(d[1]) < 1e-12) {
        const Frame g(theta);
        law_->evaluate(E - beta * g.vt, h, re);
        beta_out = beta;
        theta_out = theta;
        return re.S.allFinite() && beta <= 1e-12 && g.vn.dot(re.S) > 0 &&
               Vec2(g.vt.dot(re.S), g.vnt.dot(re.S)).norm() <= 1e-9 * g.vn.dot(re.S);
      }
    }
    return false;
  };

  // Guesses: the linear law's tension field for the tangent at E, and the major principal
  // strain's direction (the exact angle of an isotropic law). The admissible root of lowest
  // energy wins, as for the linear law.
  const TensionField lin = tension_field(r.C, r.S);
  double guesses[2][2] = {{lin.beta, lin.angle}, {0.0, major_angle({E[0], E[1], 0.5 * E[2]})}};
  const int first = lin.state == WrinkleState::kWrinkled ? 0 : 1;
  double best_energy = 0;
  bool found = false;
  for (int g = first; g < 2; ++g) {
    double beta = 0, theta = 0;
    if (!newton(guesses[g][0], guesses[g][1], beta, theta)) continue;
    const Vec3 Ee = E - beta * Frame(theta).vt;
    const double W = law_->energy(Ee, h);
    if (found && !(W < best_energy - 1e-14 * std::abs(best_energy))) continue;
    found = true;
    best_energy = W;
    sol.beta = beta;
    sol.theta = theta;
    sol.Ee = Ee;
  }
  if (!found) {
    sol.state = WrinkleState::kSlack;
    out.S.setZero();
    out.C = kappa_ * r.C;
    out.state = WrinkleState::kSlack;
    out.angle = 0;
    return sol;
  }
  sol.state = WrinkleState::kWrinkled;
  sol.theta = std::fmod(sol.theta, std::numbers::pi);
  if (sol.theta < 0) sol.theta += std::numbers::pi;
  const Frame f(sol.theta);
  law_->evaluate(sol.Ee, h, re);
  const double beta = sol.beta, s = f.vn.dot(re.S);
  const Vec3 Cvt = re.C * f.vt, Cvnt = re.C * f.vnt;
  Mat2 J;
  J << -f.vt.dot(Cvt), 2 * beta * f.vt.dot(Cvnt), -f.vnt.dot(Cvt), -s + 2 * beta * f.vnt.dot(Cvnt);
  Eigen::Matrix<double, 2, 3> dRdE;
  dRdE.row(0) = (re.C.transpose() * f.vt).transpose();
  dRdE.row(1) = (re.C.transpose() * f.vnt).transpose();
  const Eigen::Matrix<double, 2, 3> dx = -J.inverse() * dRdE;  // d(β, θ)/dE
  Eigen::Matrix<double, 3, 2> dSdx;
  dSdx.col(0) = -Cvt;
  dSdx.col(1) = 2 * beta * Cvnt;
  out.S = re.S;
  out.C = re.C + dSdx * dx + kappa_ * r.C;
  out.state = WrinkleState::kWrinkled;
  out.angle = sol.theta;
  return sol;
}

void TensionFieldSheetLaw::evaluate(const Vec3& E, std::span<const double> h,
                                    SheetResponse& out) const {
  solve(E, h, out);
}

double TensionFieldSheetLaw::energy(const Vec3& E, std::span<const double> h) const {
  SheetResponse r;
  const Solution sol = solve(E, h, r);
  switch (sol.state) {
    case WrinkleState::kTaut:
      return law_->energy(E, h);
    case WrinkleState::kWrinkled:
      return law_->energy(sol.Ee, h);
    case WrinkleState::kSlack:
      return slack_energy_;
  }
  return law_->energy(E, h);
}

void TensionFieldSheetLaw::update_state(const Vec3& E, std::span<double> h) const {
  SheetResponse r;
  const Solution sol = solve(E, h, r);
  if (sol.state == WrinkleState::kSlack) return;
  law_->update_state(sol.state == WrinkleState::kWrinkled ? sol.Ee : E, h);
}

double TensionFieldSheetLaw::thickness_ratio(const Vec3& E, std::span<const double> h) const {
  SheetResponse r;
  const Solution sol = solve(E, h, r);
  return law_->thickness_ratio(sol.state == WrinkleState::kWrinkled ? sol.Ee : E, h);
}

}  // namespace velum
