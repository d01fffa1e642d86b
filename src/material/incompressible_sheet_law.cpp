#include "velum/material/incompressible_sheet_law.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "velum/material/plane_stress.hpp"
#include "voigt_pairs.hpp"

namespace velum {
namespace {

using voigt_pairs::kI;
using voigt_pairs::kJ;
using voigt_pairs::voigt;

/// (A ⊗ B)_{ijkl} = A_ij B_kl as a Voigt matrix (rows ij, columns kl).
Mat3 outer(const Mat2& A, const Mat2& B) {
  return voigt(A) * voigt(B).transpose();
}
/// (A ⊙ A)_{ijkl} = ½ (A_ik A_jl + A_il A_jk): −∂(C⁻¹)/∂C for A = C⁻¹.
Mat3 odot(const Mat2& A) {
  Mat3 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int i = kI[r], j = kJ[r], k = kI[c], l = kJ[c];
      out(r, c) = 0.5 * (A(i, k) * A(j, l) + A(i, l) * A(j, k));
    }
  return out;
}

}  // namespace

IncompressibleSheetLaw IncompressibleSheetLaw::neo_hookean(const std::string& name, double mu) {
  if (!(mu > 0))
    throw MaterialError(
        fmt::format("material '{}': the shear modulus mu must be positive (got {})", name, mu));
  return {name, 0.5 * mu, 0.0};
}

IncompressibleSheetLaw IncompressibleSheetLaw::mooney_rivlin(const std::string& name, double C1,
                                                             double C2) {
  if (!(C1 + C2 > 0))
    throw MaterialError(fmt::format(
        "material '{}': C1 + C2 = {} must be positive (the small-strain shear modulus is "
        "2 (C1 + C2))",
        name, C1 + C2));
  if (!(C1 >= 0))
    throw MaterialError(fmt::format(
        "material '{}': C1 = {} must not be negative (with C1 < 0 the sheet loses stability "
        "at a uniaxial stretch of -C2/C1 = {:.4g}: C1 >= 0 and C2 >= 0 keep it stable at "
        "every stretch)",
        name, C1, -C2 / C1));
  if (!(C2 >= 0))
    throw MaterialError(fmt::format(
        "material '{}': C2 = {} must not be negative (with C2 < 0 the sheet softens and "
        "loses stability at an equibiaxial stretch of sqrt(-C1/C2) = {:.4g}: C1 >= 0 and "
        "C2 >= 0 keep it stable at every stretch)",
        name, C2, std::sqrt(-C1 / C2)));
  return {name, C1, C2};
}

IncompressibleSheetLaw::IncompressibleSheetLaw(std::string name, double C1, double C2)
    : name_(std::move(name)), C1_(C1), C2_(C2) {
  SheetResponse r;
  evaluate(Vec3::Zero(), {}, r);
  Q0_ = r.C;
}

void IncompressibleSheetLaw::evaluate(const Vec3& E, std::span<const double>,
                                      SheetResponse& out) const {
  Mat2 C;
  C << 1 + 2 * E[0], E[2], E[2], 1 + 2 * E[1];
  const double d = C(0, 0) * C(1, 1) - C(0, 1) * C(0, 1);
  out.state = WrinkleState::kTaut;
  if (!(d > 0)) {
    out.S.setConstant(std::numeric_limits<double>::quiet_NaN());
    out.C.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  Mat2 A;  // C⁻¹
  A << C(1, 1) / d, -C(0, 1) / d, -C(0, 1) / d, C(0, 0) / d;
  const Mat2 I = Mat2::Identity();
  const double id = 1 / d, g = C.trace() * id;
  // ∂I1/∂C = I − C⁻¹/d; ∂I2/∂C = d C⁻¹ + I/d − (tr C/d) C⁻¹.
  const Mat2 dI1 = I - id * A;
  const Mat2 dI2 = d * A + id * I - g * A;
  out.S = voigt(2 * (C1_ * dI1 + C2_ * dI2));
  // ∂²I1/∂C² = (A⊗A + A⊙A)/d;
  // ∂²I2/∂C² = d (A⊗A − A⊙A) − (I⊗A + A⊗I)/d + g (A⊗A + A⊙A). dS/dE = 4 ∂²W/∂C².
  const Mat3 AA = outer(A, A), AoA = odot(A);
  Mat3 H = C1_ * id * (AA + AoA);
  if (C2_ != 0) H += C2_ * (d * (AA - AoA) - id * (outer(I, A) + outer(A, I)) + g * (AA + AoA));
  out.C = 4 * H;
}

double IncompressibleSheetLaw::energy(const Vec3& E, std::span<const double>) const {
  const double a = 1 + 2 * E[0], b = 1 + 2 * E[1], d = a * b - E[2] * E[2];
  if (!(d > 0)) return std::numeric_limits<double>::infinity();
  const double I1 = a + b + 1 / d, I2 = d + (a + b) / d;
  return C1_ * (I1 - 3) + C2_ * (I2 - 3);
}

double IncompressibleSheetLaw::thickness_ratio(const Vec3& E, std::span<const double>) const {
  const double d = (1 + 2 * E[0]) * (1 + 2 * E[1]) - E[2] * E[2];
  return d > 0 ? 1 / std::sqrt(d) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace velum
