#include "velum/material/sheet_law.hpp"

#include <stdexcept>

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
  linear_or_throw("a sheet prestress").with_prestress(S0);
  return *this;
}

SheetLaw& SheetLaw::with_wrinkling(double kappa) {
  linear_or_throw("wrinkling").with_wrinkling(kappa);
  return *this;
}

double SheetLaw::slack_stiffness() const {
  const LinearSheetLaw* l = linear();
  return l ? l->slack_stiffness() : 0.0;
}

SheetLaw form_finding_law(const SheetLaw& law, double stabilizer) {
  const Mat3& Q = law.reference_stiffness();
  const Vec3 S0 = law.prestress();
  const double q = Q.diagonal().maxCoeff();
  const double s0 = S0.cwiseAbs().maxCoeff();
  return SheetLaw(PlaneStressLaw::matrix(law.name(), (stabilizer * s0 / q) * Q)).with_prestress(S0);
}

}  // namespace velum
