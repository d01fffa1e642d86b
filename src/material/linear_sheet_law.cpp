#include "velum/material/linear_sheet_law.hpp"

#include <Eigen/QR>
#include <cmath>
#include <numbers>

namespace velum {

namespace {

/// A fibre family's direction n as the stress-Voigt vector of n ⊗ n, [c², s², c s]: its
/// strain is v · E (engineering E) and its stress contributes E_f ε_f v.
Vec3 fiber_vector(const FiberFamily& f) {
  const double th = f.angle_deg * std::numbers::pi / 180, c = std::cos(th), s = std::sin(th);
  return {c * c, s * s, c * s};
}

}  // namespace

LinearSheetLaw& LinearSheetLaw::with_prestress(const Vec3& S0) {
  if (wrinkling_ && !elastic_.families().empty() && S0.squaredNorm() > 0)
    throw MaterialError("material '" + elastic_.name() +
                        "': a fibre sheet that wrinkles takes no sheet prestress (its fibres "
                        "go slack one by one; give the fibres' cables a prestress instead)");
  S0_ = S0;
  // The energy of a stress-free state: min over E of ½ EᵀQE + S0·E = −½ S0ᵀ Q⁺ S0.
  const Mat3 Qplus = elastic_.Q().completeOrthogonalDecomposition().pseudoInverse();
  slack_energy_ = -0.5 * S0_.dot(Qplus * S0_);
  return *this;
}

LinearSheetLaw& LinearSheetLaw::with_wrinkling(double kappa) {
  if (!(kappa >= 0 && kappa < 1))
    throw MaterialError("the residual stiffness of a wrinkling sheet must lie in [0, 1)");
  if (!elastic_.families().empty() && S0_.squaredNorm() > 0)
    throw MaterialError("material '" + elastic_.name() +
                        "': a fibre sheet that wrinkles takes no sheet prestress (its fibres "
                        "go slack one by one; give the fibres' cables a prestress instead)");
  wrinkling_ = true;
  kappa_ = kappa;
  return *this;
}

void LinearSheetLaw::evaluate(const Vec3& E, SheetResponse& out) const {
  const Mat3& Q = elastic_.Q();
  const Vec3 St = Q * E + S0_;
  if (!wrinkling_) {
    out.S = St;
    out.C = Q;
    out.state = WrinkleState::kTaut;
    return;
  }
  if (!elastic_.families().empty()) {
    fiber_tension_field(E, out);
    return;
  }
  const TensionField tf = tension_field(Q, St);
  out.state = tf.state;
  out.angle = tf.angle;
  if (tf.state == WrinkleState::kTaut) {
    out.S = St;
    out.C = Q;
    return;
  }
  // The stress is the tension field's alone: a share of the trial stress would put a
  // compression κ S_trial into every wrinkled and slack point, whose forces Newton must then
  // balance on a stiffness of κ Q (docs/wrinkling.md, "Residual stiffness"). The residual
  // stiffness regularises the tangent only.
  out.S = tf.S;
  out.C = tf.C + kappa_ * Q;
}

void LinearSheetLaw::stress(const Vec3& E, SheetResponse& out) const {
  if (!wrinkling_ || !elastic_.families().empty()) {
    evaluate(E, out);
    return;
  }
  const Mat3& Q = elastic_.Q();
  const Vec3 St = Q * E + S0_;
  const TensionField tf = tension_field(Q, St, false);
  out.state = tf.state;
  out.angle = tf.angle;
  out.S = tf.state == WrinkleState::kTaut ? St : tf.S;
}

void LinearSheetLaw::fiber_tension_field(const Vec3& E, SheetResponse& out) const {
  // A sheet of fibre families has no stiffness across its fibres, so its tension field is
  // each family going slack on its own (a fibre carries no compression); the residual
  // fraction κ of the elastic law is added to the tangent only, as for other sheets.
  out.S.setZero();
  out.C.setZero();
  int taut = 0;
  for (const auto& f : elastic_.families()) {
    const Vec3 v = fiber_vector(f);
    const double eps = v.dot(E);
    if (eps > 0) {
      out.S += f.E * eps * v;
      out.C += f.E * v * v.transpose();
      ++taut;
      out.angle = f.angle_deg * std::numbers::pi / 180;
    }
  }
  const int n = static_cast<int>(elastic_.families().size());
  if (taut < n) out.C += kappa_ * elastic_.Q();
  out.state = taut == n   ? WrinkleState::kTaut
              : taut == 0 ? WrinkleState::kSlack
                          : WrinkleState::kWrinkled;
  if (out.state != WrinkleState::kWrinkled) out.angle = 0;
}

double LinearSheetLaw::energy(const Vec3& E) const {
  const Mat3& Q = elastic_.Q();
  const double W = 0.5 * E.dot(Q * E) + S0_.dot(E);
  if (!wrinkling_) return W;
  if (!elastic_.families().empty()) {
    double Wf = 0;
    for (const auto& f : elastic_.families()) {
      const double eps = fiber_vector(f).dot(E);
      if (eps > 0) Wf += 0.5 * f.E * eps * eps;
    }
    return Wf;
  }
  const TensionField tf = tension_field(Q, Q * E + S0_);
  switch (tf.state) {
    case WrinkleState::kTaut:
      return W;
    case WrinkleState::kSlack:
      return slack_energy_;
    case WrinkleState::kWrinkled: {
      // W(E − β v_t) = W(E) − ½ β² v_tᵀQv_t at the root (tension_field.cpp).
      const double c = std::cos(tf.angle), s = std::sin(tf.angle);
      const Vec3 vt(s * s, c * c, -2 * s * c);
      return W - 0.5 * tf.beta * tf.beta * vt.dot(Q * vt);
    }
  }
  return W;
}

}  // namespace velum
