// An elastic-plastic sheet (ETFE foil): isotropic elasticity (E, ν) in plane stress, von Mises
// yield σ_eq = √(S11² + S22² − S11 S22 + 3 S12²) ≤ σ_y(α), associative flow and isotropic
// hardening in the equivalent plastic strain α (bilinear σ_y = σ_y0 + H α, or a tabulated
// curve, linear between its points and along its last segment beyond), elastic unloading.
// Written on the Green-Lagrange strain and the 2nd Piola-Kirchhoff stress with an additive
// split E = E_e + E_p (a small-strain law on those measures: for foils whose elastic strains
// are small, as ETFE's are); the plane-stress return map and its algorithmic (consistent)
// tangent of Simo and Taylor. History per point: E_p (engineering Voigt) and α, 4 doubles.
// Strains and stresses in the sheet axes, engineering Voigt; units the user's.
#pragma once

#include <utility>
#include <vector>

#include "velum/material/sheet_law_base.hpp"

namespace velum {

class PlasticSheetLaw final : public SheetLawBase {
 public:
  static constexpr int kStateSize = 4;  ///< E_p11, E_p22, 2 E_p12, α

  /// Bilinear hardening: σ_y = yield + hardening α (hardening ≥ 0).
  static PlasticSheetLaw bilinear(const std::string& name, double E, double nu, double yield,
                                  double hardening);
  /// A tabulated curve of (α, σ_y) points, α from 0 ascending, σ_y > 0 not falling.
  static PlasticSheetLaw tabulated(const std::string& name, double E, double nu,
                                   std::vector<std::pair<double, double>> curve);

  const std::string& name() const override { return name_; }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  /// The incremental potential ½ E_eᵀ C E_e + ∫₀^α σ_y dα of the step from h: its gradient is
  /// the return-mapped stress.
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return C_; }
  int state_size() const override { return kStateSize; }
  void initial_state(std::span<double> h) const override;
  void update_state(const Vec3& E, std::span<double> h) const override;
  double plastic_strain(std::span<const double> h) const override { return h[3]; }
  bool yields() const override { return true; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<PlasticSheetLaw>(*this);
  }

  /// The yield stress at α, and its slope.
  double yield_stress(double alpha, double* slope = nullptr) const;

  /// The return map at E from the history h: stress, tangent, the new E_p and α.
  struct Return {
    Vec3 S, Ep;
    Mat3 C;
    double alpha = 0, dgamma = 0;
  };
  Return return_map(const Vec3& E, std::span<const double> h) const;

 private:
  PlasticSheetLaw(std::string name, double E, double nu,
                  std::vector<std::pair<double, double>> curve);

  std::string name_;
  Mat3 C_, Cinv_;
  std::vector<std::pair<double, double>> curve_;  ///< (α, σ_y); two points for bilinear
};

}  // namespace velum
