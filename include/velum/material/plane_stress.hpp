// Linear-elastic plane-stress laws of a membrane sheet (docs/theory.md), between the 2nd
// Piola-Kirchhoff stress and the Green-Lagrange strain (St. Venant-Kirchhoff).
// Every law reduces to Q, the 3x3 engineering-Voigt stiffness in the sheet's principal
// axes (m1, m2): [S11, S22, S12] = Q [E11, E22, 2 E12]. Units are the user's.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "velum/math/types.hpp"

namespace velum {

/// A material whose parameters cannot describe a stable elastic sheet. The message names the
/// material and the violated condition.
class MaterialError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Engineering constants of an anisotropic sheet in its principal axes.
struct AnisotropicConstants {
  double E1 = 0, E2 = 0, nu12 = 0;
  double G12 = 0;             ///< in-plane shear modulus; ignored when use_firt
  bool use_firt = false;      ///< G12 from Firt's approximation (Eq. 19)
  double eta1 = 0, eta2 = 0;  ///< Lekhnitskii coefficients of mutual influence
};

/// One family of straight fibres at `angle_deg` from m1, modulus E per unit sheet thickness.
struct FiberFamily {
  double E = 0;
  double angle_deg = 0;
};

/// Firt's approximation of the shear modulus: sqrt(E1 E2) / (2 (1 + sqrt(nu12 nu21))).
double firt_shear_modulus(double E1, double E2, double nu12);

/// Compliance S of Eq. 15 (engineering Voigt), with nu21 = nu12 E2/E1.
Mat3 compliance(const AnisotropicConstants& c);

/// A plane-stress law: the stiffness Q in the sheet axes. Value type; immutable after build.
class PlaneStressLaw {
 public:
  static PlaneStressLaw isotropic(const std::string& name, double E, double nu);
  static PlaneStressLaw orthotropic(const std::string& name, double E1, double E2, double nu12,
                                    double G12, bool use_firt);
  /// Closed-form Q of Eq. 21; rejects non-admissible constants.
  static PlaneStressLaw anisotropic(const std::string& name, const AnisotropicConstants& c);
  /// Q^{abcd} = sum_f E_f n_a n_b n_c n_d, n = (cos, sin) of the fibre angle (exact tensor).
  static PlaneStressLaw fibers(const std::string& name, const std::vector<FiberFamily>& families);
  /// Q given directly in engineering Voigt; must be symmetric and positive semi-definite.
  static PlaneStressLaw matrix(const std::string& name, const Mat3& Q);

  const Mat3& Q() const { return Q_; }
  const std::string& name() const { return name_; }
  /// The fibre families of a `fibers` law (empty for the others).
  const std::vector<FiberFamily>& families() const { return families_; }

  /// [S11, S22, S12] for engineering strain [E11, E22, 2 E12], in the sheet axes.
  Vec3 stress(const Vec3& strain_voigt) const { return Q_ * strain_voigt; }
  /// d stress / d strain (constant for this law).
  const Mat3& tangent() const { return Q_; }

 private:
  PlaneStressLaw(std::string name, const Mat3& Q) : name_(std::move(name)), Q_(Q) {}
  std::string name_;
  Mat3 Q_ = Mat3::Zero();
  std::vector<FiberFamily> families_;
};

/// Transforms a 2-D fourth-order stiffness given in engineering Voigt form between frames:
/// out^{αβγδ} = Q^{abcd} T(a,α) T(b,β) T(c,γ) T(d,δ), returned again as engineering Voigt
/// (so that [S^11, S^22, S^12] = out [γ11, γ22, 2γ12]). T(a,α) = m_a · G^α for the convected
/// frame (docs/theory.md); a rotation matrix for a change of orthonormal axes.
Mat3 transform_stiffness(const Mat3& Q, const Mat2& T);

}  // namespace velum
