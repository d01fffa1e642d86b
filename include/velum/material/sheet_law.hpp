// The constitutive law of a membrane section as sections, blocks and the kernels hold it: any
// SheetLawBase (sheet_law_base.hpp) behind one copyable value (a copy clones the law). Built
// from a plane-stress law it is the linear anisotropic law (linear_sheet_law.hpp), which also
// takes a prestress and wrinkling. Strains and stresses in the sheet's principal axes,
// engineering Voigt (E = [E11, E22, 2 E12], S = [S11, S22, S12]). Units are the user's.
#pragma once

#include <concepts>
#include <memory>

#include "velum/material/linear_sheet_law.hpp"
#include "velum/material/sheet_law_base.hpp"

namespace velum {

class SheetLaw {
 public:
  static constexpr double kDefaultSlackStiffness = LinearSheetLaw::kDefaultSlackStiffness;

  /// The linear law of an elastic plane-stress law (implicit: every plane-stress law is a
  /// sheet law).
  SheetLaw(const PlaneStressLaw& elastic)  // NOLINT(google-explicit-constructor)
      : law_(std::make_unique<LinearSheetLaw>(elastic)) {}
  /// Any law, by value (implicit, as a law is a sheet law).
  template <std::derived_from<SheetLawBase> Law>
  SheetLaw(Law law)  // NOLINT(google-explicit-constructor)
      : law_(std::make_unique<Law>(std::move(law))) {}
  explicit SheetLaw(std::unique_ptr<SheetLawBase> law);

  SheetLaw(const SheetLaw& o) : law_(o.law_->clone()) {}
  SheetLaw& operator=(const SheetLaw& o) {
    if (this != &o) law_ = o.law_->clone();
    return *this;
  }
  SheetLaw(SheetLaw&&) noexcept = default;
  SheetLaw& operator=(SheetLaw&&) noexcept = default;
  ~SheetLaw() = default;

  /// The law itself.
  const SheetLawBase& base() const { return *law_; }
  /// The linear law behind this one, or null when it is another law.
  const LinearSheetLaw* linear() const { return dynamic_cast<const LinearSheetLaw*>(law_.get()); }

  // The interface (SheetLawBase), for a point without history.
  const std::string& name() const { return law_->name(); }
  void evaluate(const Vec3& E, SheetResponse& out) const { law_->evaluate(E, {}, out); }
  double energy(const Vec3& E) const { return law_->energy(E, {}); }
  /// SheetLawBase::stress: the stress without its tangent.
  void stress(const Vec3& E, SheetResponse& out) const { law_->stress(E, {}, out); }
  void stress(const Vec3& E, std::span<const double> h, SheetResponse& out) const {
    law_->stress(E, h, out);
  }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const {
    law_->evaluate(E, h, out);
  }
  double energy(const Vec3& E, std::span<const double> h) const { return law_->energy(E, h); }
  bool affine() const { return law_->affine(); }
  const Mat3& reference_stiffness() const { return law_->reference_stiffness(); }
  /// The reference stiffness (Q of the linear law).
  const Mat3& Q() const { return law_->reference_stiffness(); }
  Vec3 prestress() const { return law_->prestress(); }
  bool has_prestress() const { return prestress().squaredNorm() > 0; }
  bool wrinkling() const { return law_->wrinkling(); }
  int state_size() const { return law_->state_size(); }
  /// The current thickness over the reference thickness at E (1 unless the law thins).
  double thickness_ratio(const Vec3& E) const { return law_->thickness_ratio(E, {}); }
  bool thins() const { return law_->thins(); }
  /// The equivalent plastic strain in the history h (0 unless the law yields).
  double plastic_strain(std::span<const double> h) const { return law_->plastic_strain(h); }
  bool yields() const { return law_->yields(); }

  // What a section adds: the linear law's own closed forms, or for any other law its wrappers
  // (sheet_law_wrappers.hpp).
  /// Prestress S0 = [S11, S22, S12] (2nd PK, sheet axes, force/area).
  SheetLaw& with_prestress(const Vec3& S0);
  /// Tension field with residual stiffness fraction kappa in [0, 1).
  SheetLaw& with_wrinkling(double kappa = kDefaultSlackStiffness);
  /// The residual stiffness fraction where the sheet wrinkles (0 without wrinkling).
  double slack_stiffness() const;

 private:
  LinearSheetLaw& linear_or_throw(const char* what);

  std::unique_ptr<SheetLawBase> law_;  // never null
};

/// The law form finding gives a prestressed sheet: its prestress S0 on the elastic law of its
/// reference stiffness, scaled so that the stiffness's largest diagonal entry is `stabilizer`
/// times the largest |S0| component; no wrinkling. `law` has a prestress.
SheetLaw form_finding_law(const SheetLaw& law, double stabilizer);

}  // namespace velum
