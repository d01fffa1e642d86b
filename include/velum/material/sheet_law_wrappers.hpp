// What a section adds to a sheet law other than the linear one (which has its own, faster,
// closed forms in linear_sheet_law.hpp): a prestress added to the law's stress, and the
// tension field (wrinkling) of any law, solved on the law's own response. Each wraps the law
// it modifies. Strains and stresses in the sheet axes, engineering Voigt; units the user's.
#pragma once

#include <memory>

#include "velum/material/sheet_law_base.hpp"

namespace velum {

/// S = S_law(E) + S0, C = C_law(E); W = W_law(E) + S0 · E (2nd PK S0, sheet axes).
class PrestressedSheetLaw final : public SheetLawBase {
 public:
  PrestressedSheetLaw(std::unique_ptr<SheetLawBase> law, const Vec3& S0);
  PrestressedSheetLaw(const PrestressedSheetLaw& o) : law_(o.law_->clone()), S0_(o.S0_) {}

  const SheetLawBase& law() const { return *law_; }
  const std::string& name() const override { return law_->name(); }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return law_->affine(); }
  const Mat3& reference_stiffness() const override { return law_->reference_stiffness(); }
  Vec3 prestress() const override { return law_->prestress() + S0_; }
  double thickness_ratio(const Vec3& E, std::span<const double> h) const override {
    return law_->thickness_ratio(E, h);
  }
  bool thins() const override { return law_->thins(); }
  double plastic_strain(std::span<const double> h) const override {
    return law_->plastic_strain(h);
  }
  bool yields() const override { return law_->yields(); }
  int state_size() const override { return law_->state_size(); }
  void initial_state(std::span<double> h) const override { law_->initial_state(h); }
  void update_state(const Vec3& E, std::span<double> h) const override { law_->update_state(E, h); }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<PrestressedSheetLaw>(*this);
  }

 private:
  std::unique_ptr<SheetLawBase> law_;
  Vec3 S0_;
};

/// The tension field of a law S(E) (docs/wrinkling.md): taut where S(E) has no negative
/// principal value; otherwise wrinkled, S = S(E − β t⊗t) with uniaxial tension s > 0 along
/// n = (cos θ, sin θ) and a wrinkling strain β ≤ 0 across it (t ⟂ n), solved by Newton on
/// (β, θ) from the linear law's solution for the tangent at E (tension_field); slack (S = 0)
/// when no such state exists. The tangent is exact (implicit differentiation of the two
/// conditions t·S·t = 0, n·S·t = 0), plus κ C(E) as the linear law's residual stiffness.
class TensionFieldSheetLaw final : public SheetLawBase {
 public:
  TensionFieldSheetLaw(std::unique_ptr<SheetLawBase> law, double kappa);
  TensionFieldSheetLaw(const TensionFieldSheetLaw& o)
      : law_(o.law_->clone()), kappa_(o.kappa_), slack_energy_(o.slack_energy_) {}

  const SheetLawBase& law() const { return *law_; }
  double slack_stiffness() const { return kappa_; }
  const std::string& name() const override { return law_->name(); }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  /// W(E − β t⊗t) where wrinkled; where slack, the small-strain estimate of the prestress's
  /// stress-free energy −½ S0ᵀQ⁺S0 (0 without prestress).
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return law_->reference_stiffness(); }
  Vec3 prestress() const override { return law_->prestress(); }
  bool wrinkling() const override { return true; }
  /// The law's thickness at the elastic strain E − β t⊗t (a slack point keeps E's).
  double thickness_ratio(const Vec3& E, std::span<const double> h) const override;
  bool thins() const override { return law_->thins(); }
  double plastic_strain(std::span<const double> h) const override {
    return law_->plastic_strain(h);
  }
  bool yields() const override { return law_->yields(); }
  int state_size() const override { return law_->state_size(); }
  void initial_state(std::span<double> h) const override { law_->initial_state(h); }
  /// The law's history moves on at the strain it is evaluated at: E where taut, the elastic
  /// strain E − β t⊗t where wrinkled; a slack point carries no stress and keeps its history.
  void update_state(const Vec3& E, std::span<double> h) const override;
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<TensionFieldSheetLaw>(*this);
  }

  /// The solve behind evaluate(): the state, and for a wrinkled point β, θ and the elastic
  /// strain E − β t⊗t at which the law is evaluated.
  struct Solution {
    WrinkleState state = WrinkleState::kTaut;
    double beta = 0, theta = 0;
    Vec3 Ee = Vec3::Zero();
  };
  Solution solve(const Vec3& E, std::span<const double> h, SheetResponse& out) const;

 private:
  std::unique_ptr<SheetLawBase> law_;
  double kappa_;
  double slack_energy_ = 0;
};

}  // namespace velum
