// Incompressible isotropic hyperelastic sheets (rubber, silicone): the Mooney-Rivlin family
// W = C1 (I1 − 3) + C2 (I2 − 3) per unit reference volume, neo-Hookean for C2 = 0 (μ = 2 C1),
// in plane stress through the thickness: with C the in-plane right Cauchy-Green tensor (2x2,
// C = I + 2E in the reference sheet axes) the stretch across the sheet is λ3² = 1/det C, so
// I1 = tr C + 1/det C, I2 = det C + tr C/det C and the thickness h = H/√det C. Stress
// S = 2 ∂W/∂C and tangent 4 ∂²W/∂C² in closed form. Strains and stresses in the sheet axes,
// engineering Voigt; units are the user's (μ, C1, C2 force/area).
#pragma once

#include "velum/material/sheet_law_base.hpp"

namespace velum {

class IncompressibleSheetLaw final : public SheetLawBase {
 public:
  /// W = μ/2 (I1 − 3); μ > 0 (a MaterialError naming the material otherwise).
  static IncompressibleSheetLaw neo_hookean(const std::string& name, double mu);
  /// W = C1 (I1 − 3) + C2 (I2 − 3); stable at every stretch when C1 ≥ 0, C2 ≥ 0 and
  /// C1 + C2 > 0 (the small-strain shear modulus 2 (C1 + C2)): a MaterialError names the
  /// condition that fails.
  static IncompressibleSheetLaw mooney_rivlin(const std::string& name, double C1, double C2);

  double C1() const { return C1_; }
  double C2() const { return C2_; }
  /// Small-strain shear modulus 2 (C1 + C2).
  double shear_modulus() const { return 2 * (C1_ + C2_); }

  const std::string& name() const override { return name_; }
  /// S and dS/dE at E; NaN where det C ≤ 0 (no sheet: the element has folded flat).
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return false; }
  /// 2μ (I⊗I + I⊙I): E = 3μ, ν = 1/2 in plane stress.
  const Mat3& reference_stiffness() const override { return Q0_; }
  /// h/H = 1/√det C.
  double thickness_ratio(const Vec3& E, std::span<const double> h) const override;
  bool thins() const override { return true; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<IncompressibleSheetLaw>(*this);
  }

 private:
  IncompressibleSheetLaw(std::string name, double C1, double C2);

  std::string name_;
  double C1_, C2_;
  Mat3 Q0_;
};

}  // namespace velum
