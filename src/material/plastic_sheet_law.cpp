// The plane-stress return map (Simo and Taylor 1986; Simo and Hughes, Computational
// Inelasticity, §3.4). With P the plane-stress deviatoric projection in engineering Voigt
// form, ½ SᵀPS = σ_eq²/3 and the yield function F = ½ SᵀPS − σ_y(α)²/3. Backward Euler:
//   S = Ξ(Δγ) (E − E_p,n),  Ξ = (C⁻¹ + Δγ P)⁻¹,  E_p = E_p,n + Δγ P S,
//   α = α_n + Δγ r,  r = √(2/3 SᵀPS),
// and F(Δγ) = 0 solved for Δγ ≥ 0 (a scalar Newton iteration kept inside a bracket).
// The algorithmic tangent follows by differentiating these at the solution:
//   dS/dE = Ξ − n nᵀ / (ψ + c2/c1),  n = Ξ P S,  ψ = Sᵀ P Ξ P S,
//   c1 = 1 − (4/9) σ_y σ_y' Δγ / r,  c2 = (2/3) σ_y σ_y' r.
#include "velum/material/plastic_sheet_law.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "velum/material/plane_stress.hpp"

namespace velum {
namespace {

const Mat3& projection() {
  static const Mat3 P = [] {
    Mat3 m;
    m << 2, -1, 0, -1, 2, 0, 0, 0, 6;
    return Mat3(m / 3);
  }();
  return P;
}

}  // namespace

PlasticSheetLaw PlasticSheetLaw::bilinear(const std::string& name, double E, double nu,
                                          double yield, double hardening) {
  if (!(yield > 0))
    throw MaterialError(
        fmt::format("material '{}': the yield stress must be positive (got {})", name, yield));
  if (!(hardening >= 0))
    throw MaterialError(fmt::format(
        "material '{}': the hardening modulus must not be negative (got {})", name, hardening));
  return {name, E, nu, {{0.0, yield}, {1.0, yield + hardening}}};
}

PlasticSheetLaw PlasticSheetLaw::tabulated(const std::string& name, double E, double nu,
                                           std::vector<std::pair<double, double>> curve) {
  if (curve.empty())
    throw MaterialError(fmt::format("material '{}': the hardening curve has no points", name));
  if (curve[0].first != 0)
    throw MaterialError(
        fmt::format("material '{}': the hardening curve must start at plastic strain 0 (got {})",
                    name, curve[0].first));
  for (size_t i = 0; i < curve.size(); ++i) {
    if (!(curve[i].second > 0))
      throw MaterialError(fmt::format(
          "material '{}': point {} of the hardening curve: the yield stress must be positive "
          "(got {})",
          name, i + 1, curve[i].second));
    if (i > 0 && !(curve[i].first > curve[i - 1].first))
      throw MaterialError(fmt::format(
          "material '{}': point {} of the hardening curve: the plastic strains must ascend "
          "({} after {})",
          name, i + 1, curve[i].first, curve[i - 1].first));
    if (i > 0 && curve[i].second < curve[i - 1].second)
      throw MaterialError(fmt::format(
          "material '{}': point {} of the hardening curve: the yield stress falls ({} after "
          "{}): softening is not stable",
          name, i + 1, curve[i].second, curve[i - 1].second));
  }
  if (curve.size() == 1) curve.emplace_back(1.0, curve[0].second);  // perfectly plastic
  return {name, E, nu, std::move(curve)};
}

PlasticSheetLaw::PlasticSheetLaw(std::string name, double E, double nu,
                                 std::vector<std::pair<double, double>> curve)
    : name_(std::move(name)), curve_(std::move(curve)) {
  C_ = PlaneStressLaw::isotropic(name_, E, nu).Q();
  Cinv_ = C_.inverse();
}

double PlasticSheetLaw::yield_stress(double alpha, double* slope) const {
  // The segment holding α (the last one beyond the curve's end).
  size_t i = 1;
  while (i + 1 < curve_.size() && alpha > curve_[i].first) ++i;
  const auto [a0, s0] = curve_[i - 1];
  const auto [a1, s1] = curve_[i];
  const double k = (s1 - s0) / (a1 - a0);
  if (slope) *slope = k;
  return s0 + k * (alpha - a0);
}

void PlasticSheetLaw::initial_state(std::span<double> h) const {
  std::fill(h.begin(), h.end(), 0.0);
}

PlasticSheetLaw::Return PlasticSheetLaw::return_map(const Vec3& E,
                                                    std::span<const double> h) const {
  const Vec3 Ep_n(h[0], h[1], h[2]);
  const double alpha_n = h[3];
  const Vec3 Ee = E - Ep_n;
  const Mat3& P = projection();
  Return out;
  out.S = C_ * Ee;
  out.C = C_;
  out.Ep = Ep_n;
  out.alpha = alpha_n;
  const double sy_n = yield_stress(alpha_n);
  if (0.5 * out.S.dot(P * out.S) <= sy_n * sy_n / 3 * (1 + 1e-14)) return out;  // elastic

  // F(Δγ) and its slope; S, Ξ and the yield stress at Δγ.
  struct At {
    Vec3 S;
    Mat3 Xi;
    double F, dF, r, sy, dsy, alpha;
  };
  auto at = [&](double dg) {
    At a;
    a.Xi = (Cinv_ + dg * P).inverse();
    a.S = a.Xi * Ee;
    const Vec3 PS = P * a.S;
    const double SPS = a.S.dot(PS);
    a.r = std::sqrt(2.0 / 3 * SPS);
    a.alpha = alpha_n + dg * a.r;
    a.sy = yield_stress(a.alpha, &a.dsy);
    const double psi = PS.dot(a.Xi * PS);
    a.F = 0.5 * SPS - a.sy * a.sy / 3;
    const double dalpha = a.r - (a.r > 0 ? 2.0 / 3 * dg * psi / a.r : 0.0);
    a.dF = -psi - 2.0 / 3 * a.sy * a.dsy * dalpha;
    return a;
  };
  double lo = 0, hi = 1 / C_.diagonal().maxCoeff();
  while (at(hi).F > 0) hi *= 2;
  double dg = 0;
  At a = at(dg);
  const double tol = 1e-15 * sy_n * sy_n;
  for (int it = 0; it < 100 && std::abs(a.F) > tol; ++it) {
    if (a.F > 0)
      lo = dg;
    else
      hi = dg;
    double next = a.dF < 0 ? dg - a.F / a.dF : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    dg = next;
    a = at(dg);
    if (hi - lo < 1e-16 * hi) break;
  }
  out.S = a.S;
  out.dgamma = dg;
  out.alpha = a.alpha;
  out.Ep = Ep_n + dg * (P * a.S);
  const Vec3 n = a.Xi * (P * a.S);
  const double psi = (P * a.S).dot(n);
  const double c1 = 1 - 4.0 / 9 * a.sy * a.dsy * dg / a.r;
  const double c2 = 2.0 / 3 * a.sy * a.dsy * a.r;
  out.C = a.Xi - n * n.transpose() / (psi + c2 / c1);
  return out;
}

void PlasticSheetLaw::evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const {
  static constexpr double kVirgin[kStateSize] = {0, 0, 0, 0};
  const Return r = return_map(E, h.empty() ? std::span<const double>(kVirgin) : h);
  out.S = r.S;
  out.C = r.C;
  out.state = WrinkleState::kTaut;
}

double PlasticSheetLaw::energy(const Vec3& E, std::span<const double> h) const {
  static constexpr double kVirgin[kStateSize] = {0, 0, 0, 0};
  const Return r = return_map(E, h.empty() ? std::span<const double>(kVirgin) : h);
  const Vec3 Ee = E - r.Ep;
  // ∫₀^α σ_y dα over the curve's segments (the last one extended).
  double work = 0;
  for (size_t i = 1; i < curve_.size() && r.alpha > curve_[i - 1].first; ++i) {
    const double a0 = curve_[i - 1].first;
    const double a1 = i + 1 < curve_.size() ? std::min(r.alpha, curve_[i].first) : r.alpha;
    work += 0.5 * (yield_stress(a0) + yield_stress(a1)) * (a1 - a0);
  }
  return 0.5 * Ee.dot(C_ * Ee) + work;
}

void PlasticSheetLaw::update_state(const Vec3& E, std::span<double> h) const {
  const Return r = return_map(E, h);
  h[0] = r.Ep[0];
  h[1] = r.Ep[1];
  h[2] = r.Ep[2];
  h[3] = r.alpha;
}

}  // namespace velum
