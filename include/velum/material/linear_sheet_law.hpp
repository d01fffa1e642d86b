// The linear anisotropic sheet law (THEORY §2, St. Venant-Kirchhoff): the elastic law Q of
// plane_stress.hpp with what a fabric needs on top of it:
//  - a prestress S0 (2nd PK, sheet axes) added to the elastic stress (the convention Kratos
//    uses for PRESTRESS_VECTOR): S = Q E + S0;
//  - a tension field (wrinkling): the sheet carries no compression; where the trial stress
//    Q E + S0 has a negative principal value the sheet wrinkles (uniaxial tension along the
//    wrinkles, solved with a wrinkling strain across them) or goes slack (no stress).
// Strains and stresses in the sheet axes, engineering Voigt. Units are the user's.
#pragma once

#include "velum/material/plane_stress.hpp"
#include "velum/material/sheet_law_base.hpp"

namespace velum {

/// Result of the tension-field solve for a trial stress (tension_field below).
struct TensionField {
  Vec3 S = Vec3::Zero();  ///< tension-field stress (no residual stiffness)
  Mat3 C = Mat3::Zero();  ///< its tangent dS/dE
  WrinkleState state = WrinkleState::kTaut;
  double angle = 0;  ///< wrinkled: tension direction n = (cos, sin) in the sheet axes
  double beta = 0;   ///< wrinkled: wrinkling strain across the wrinkles (<= 0, a contraction)
};

/// Tension field of the elastic law Q at the trial stress S_trial = Q E + S0 (the theory in
/// docs/wrinkling.md): taut when S_trial has no negative principal value; otherwise the
/// wrinkled state S = S_trial − β Q v(t) with uniaxial tension s > 0 along n = (cos θ, sin θ)
/// and a contraction β < 0 across it (t ⟂ n), the admissible root of lowest elastic energy;
/// slack (S = 0, C = 0) when no admissible root exists. A `fibers` law (no stiffness across
/// its fibres) is treated by LinearSheetLaw fibre by fibre instead: each family goes slack
/// alone.
/// Without `tangent`, C is left zero (the stress alone: the same S, state, angle and β).
TensionField tension_field(const Mat3& Q, const Vec3& S_trial, bool tangent = true);

class LinearSheetLaw final : public SheetLawBase {
 public:
  /// Fraction of the elastic law kept where the sheet wrinkles or goes slack, so that a slack
  /// region keeps a small stiffness and the Jacobian stays regular:
  /// S = (1 − κ) S_tension_field + κ (Q E + S0). Zero effect on taut points.
  static constexpr double kDefaultSlackStiffness = 1e-6;

  explicit LinearSheetLaw(const PlaneStressLaw& elastic) : elastic_(elastic) {}

  /// Prestress S0 = [S11, S22, S12] (2nd PK, sheet axes, force/area).
  LinearSheetLaw& with_prestress(const Vec3& S0);
  /// Tension field with residual stiffness fraction kappa in [0, 1).
  LinearSheetLaw& with_wrinkling(double kappa = kDefaultSlackStiffness);

  const PlaneStressLaw& elastic() const { return elastic_; }
  const Mat3& Q() const { return elastic_.Q(); }
  double slack_stiffness() const { return kappa_; }

  /// Stress and tangent at the Green-Lagrange strain E (sheet axes).
  void evaluate(const Vec3& E, SheetResponse& out) const;
  /// The stress alone (SheetLawBase::stress): the tension field without its tangent.
  void stress(const Vec3& E, SheetResponse& out) const;
  /// Strain energy density per unit reference volume, W with dW/dE = S. The prestress counts
  /// as S0 · E (it is zero in the reference state).
  double energy(const Vec3& E) const;

  // SheetLawBase: no history; affine (S = Q E + S0) unless it wrinkles.
  const std::string& name() const override { return elastic_.name(); }
  void evaluate(const Vec3& E, std::span<const double>, SheetResponse& out) const override {
    evaluate(E, out);
  }
  void stress(const Vec3& E, std::span<const double>, SheetResponse& out) const override {
    stress(E, out);
  }
  double energy(const Vec3& E, std::span<const double>) const override { return energy(E); }
  bool affine() const override { return !wrinkling_; }
  const Mat3& reference_stiffness() const override { return elastic_.Q(); }
  Vec3 prestress() const override { return S0_; }
  bool wrinkling() const override { return wrinkling_; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<LinearSheetLaw>(*this);
  }

 private:
  void fiber_tension_field(const Vec3& E, SheetResponse& out) const;

  PlaneStressLaw elastic_;
  Vec3 S0_ = Vec3::Zero();
  bool wrinkling_ = false;
  double kappa_ = 0;
  double slack_energy_ = 0;  ///< W at a stress-free state: −½ S0ᵀ Q⁺ S0
};

}  // namespace velum
