// A compressible neo-Hookean sheet (rubber or a polymer film that changes volume): W = μ/2
// (I1 − 3 − 2 ln J) + λ/2 (ln J)² per unit reference volume, in plane stress: with C the
// in-plane right Cauchy-Green tensor (C = I + 2E in the sheet axes) the stretch across the
// sheet, C33 = λ3², is the root of S33 = 0, μ (C33 − 1) + λ ln J = 0 with J² = det C · C33
// (solved at each point), so the thickness follows h = H λ3. Stress S = 2 ∂W/∂C and the
// tangent condensed for S33 = 0, in closed form. Sheet axes, engineering Voigt; units the
// user's (μ force/area).
#pragma once

#include "velum/material/sheet_law_base.hpp"

namespace velum {

class CompressibleSheetLaw final : public SheetLawBase {
 public:
  /// μ > 0 the shear modulus, ν in (−1, 0.5) Poisson's ratio at small strain (λ = 2μν/(1 −
  /// 2ν)); a MaterialError naming the material otherwise.
  static CompressibleSheetLaw neo_hookean(const std::string& name, double mu, double nu);

  double mu() const { return mu_; }
  double lambda() const { return lambda_; }

  const std::string& name() const override { return name_; }
  /// S and dS/dE at E; NaN where det C ≤ 0 (the element has folded flat).
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return false; }
  /// The plane-stress isotropic stiffness of E = 2μ (1 + ν) and ν.
  const Mat3& reference_stiffness() const override { return Q0_; }
  /// h/H = λ3 = √C33.
  double thickness_ratio(const Vec3& E, std::span<const double> h) const override;
  bool thins() const override { return true; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<CompressibleSheetLaw>(*this);
  }

  /// C33, the root of S33 = 0 for the in-plane C of det C = d > 0.
  double transverse_stretch_squared(double d) const;

 private:
  CompressibleSheetLaw(std::string name, double mu, double lambda);

  std::string name_;
  double mu_, lambda_;
  Mat3 Q0_;
};

}  // namespace velum
