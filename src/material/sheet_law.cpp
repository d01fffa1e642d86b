#include "velum/material/sheet_law.hpp"

#include <stdexcept>

#include "velum/material/sheet_law_wrappers.hpp"

namespace velum {

SheetLaw::SheetLaw(std::unique_ptr<SheetLawBase> law) : law_(std::move(law)) {
  if (!law_) throw std::invalid_argument("a sheet law needs a law");
}

LinearSheetLaw& SheetLaw::linear_or_throw(const char* what) {
  auto* linear = dynamic_cast<LinearSheetLaw*>(law_.get());
  if (!linear)
    throw MaterialError("material '" + law_->name() + "': " + what +
                        " applies to the linear sheet laws only");
  return *linear;
}

SheetLaw& SheetLaw::with_prestress(const Vec3& S0) {
  if (linear()) {
    linear_or_throw("a sheet prestress").with_prestress(S0);
    return *this;
  }
  // Any other law: its stress plus S0, under the tension field when it wrinkles (the
  // prestress is part of the stress the tension field relieves).
  if (auto* tf = dynamic_cast<const TensionFieldSheetLaw*>(law_.get())) {
    const double kappa = tf->slack_stiffness();
    law_ = std::make_unique<TensionFieldSheetLaw>(
        std::make_unique<PrestressedSheetLaw>(tf->law().clone(), S0), kappa);
    return *this;
  }
  law_ = std::make_unique<PrestressedSheetLaw>(std::move(law_), S0);
  return *this;
}

SheetLaw& SheetLaw::with_wrinkling(double kappa) {
  if (linear()) {
    linear_or_throw("wrinkling").with_wrinkling(kappa);
    return *this;
  }
  if (auto* tf = dynamic_cast<const TensionFieldSheetLaw*>(law_.get())) {
    law_ = std::make_unique<TensionFieldSheetLaw>(tf->law().clone(), kappa);
    return *this;
  }
  law_ = std::make_unique<TensionFieldSheetLaw>(std::move(law_), kappa);
  return *this;
}

double SheetLaw::slack_stiffness() const {
  if (const LinearSheetLaw* l = linear()) return l->slack_stiffness();
  if (auto* tf = dynamic_cast<const TensionFieldSheetLaw*>(law_.get()))
    return tf->slack_stiffness();
  return 0.0;
}

SheetLaw form_finding_law(const SheetLaw& law, double stabilizer) {
  const Mat3& Q = law.reference_stiffness();
  const Vec3 S0 = law.prestress();
  const double q = Q.diagonal().maxCoeff();
  const double s0 = S0.cwiseAbs().maxCoeff();
  return SheetLaw(PlaneStressLaw::matrix(law.name(), (stabilizer * s0 / q) * Q)).with_prestress(S0);
}

}  // namespace velum
