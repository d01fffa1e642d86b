#include "velum/material/compressible_sheet_law.hpp"

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

Mat2 right_cauchy_green(const Vec3& E) {
  Mat2 C;
  C << 1 + 2 * E[0], E[2], E[2], 1 + 2 * E[1];
  return C;
}

}  // namespace

CompressibleSheetLaw CompressibleSheetLaw::neo_hookean(const std::string& name, double mu,
                                                       double nu) {
  if (!(mu > 0))
    throw MaterialError(
        fmt::format("material '{}': the shear modulus mu must be positive (got {})", name, mu));
  if (!(nu > -1 && nu < 0.5))
    throw MaterialError(fmt::format(
        "material '{}': Poisson's ratio nu must lie in (-1, 0.5) for a compressible sheet (got "
        "{}; leave it out for the incompressible one)",
        name, nu));
  return {name, mu, 2 * mu * nu / (1 - 2 * nu)};
}

CompressibleSheetLaw::CompressibleSheetLaw(std::string name, double mu, double lambda)
    : name_(std::move(name)), mu_(mu), lambda_(lambda) {
  SheetResponse r;
  evaluate(Vec3::Zero(), {}, r);
  Q0_ = r.C;
}

double CompressibleSheetLaw::transverse_stretch_squared(double d) const {
  // f(c) = μ (c − 1) + λ/2 (ln d + ln c) rises with c; for λ ≥ 0 it is concave, so Newton
  // from a point left of the root climbs to it monotonically. Start from the incompressible
  // sheet's 1/d, stepping left first while f > 0 there.
  const auto f = [&](double c) {
    return mu_ * (c - 1) + 0.5 * lambda_ * (std::log(d) + std::log(c));
  };
  double c = 1 / d;
  for (int k = 0; k < 60 && f(c) > 0; ++k) c *= 0.5;
  for (int k = 0; k < 60; ++k) {
    const double step = f(c) / (mu_ + 0.5 * lambda_ / c);
    double next = c - step;
    if (!(next > 0)) next = 0.5 * c;
    if (std::abs(next - c) <= 1e-15 * c) return next;
    c = next;
  }
  return c;
}

void CompressibleSheetLaw::evaluate(const Vec3& E, std::span<const double>,
                                    SheetResponse& out) const {
  const Mat2 C = right_cauchy_green(E);
  const double d = C.determinant();
  out.state = WrinkleState::kTaut;
  out.angle = 0;
  if (!(d > 0)) {
    out.S.setConstant(std::numeric_limits<double>::quiet_NaN());
    out.C.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  const double c = transverse_stretch_squared(d);
  const double lnJ = 0.5 * (std::log(d) + std::log(c));
  const Mat2 Ci = C.inverse();
  out.S = voigt(mu_ * (Mat2::Identity() - Ci) + lambda_ * lnJ * Ci);
  // 4 ∂²W/∂C² = λ C⁻¹⊗C⁻¹ + 2 (μ − λ ln J) C⁻¹⊙C⁻¹ in 3D (C⁻¹ block-diagonal), condensed
  // for S33 = 0: D_ab − D_a33 D_33b / D_3333.
  const double m = mu_ - lambda_ * lnJ;
  const Vec3 ci = voigt(Ci);
  const double d3333 = (lambda_ + 2 * m) / (c * c);
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) {
      const int i = kI[r], j = kJ[r], k = kI[s], l = kJ[s];
      const double D = lambda_ * ci[r] * ci[s] + m * (Ci(i, k) * Ci(j, l) + Ci(i, l) * Ci(j, k));
      out.C(r, s) = D - (lambda_ * ci[r] / c) * (lambda_ * ci[s] / c) / d3333;
    }
}

double CompressibleSheetLaw::energy(const Vec3& E, std::span<const double>) const {
  const Mat2 C = right_cauchy_green(E);
  const double d = C.determinant();
  if (!(d > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double c = transverse_stretch_squared(d);
  const double lnJ = 0.5 * (std::log(d) + std::log(c));
  return 0.5 * mu_ * (C.trace() + c - 3 - 2 * lnJ) + 0.5 * lambda_ * lnJ * lnJ;
}

double CompressibleSheetLaw::thickness_ratio(const Vec3& E, std::span<const double>) const {
  const double d = right_cauchy_green(E).determinant();
  return d > 0 ? std::sqrt(transverse_stretch_squared(d))
               : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace velum
