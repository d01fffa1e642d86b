#include "velum/material/stress_map_sheet_law.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "velum/material/plane_stress.hpp"

namespace velum {

namespace {

bool strictly_increasing(const std::vector<double>& v) {
  return std::adjacent_find(v.begin(), v.end(), std::greater_equal<>()) == v.end();
}

}  // namespace

StressMapSheetLaw::StressMapSheetLaw(std::string name, StressMapData data)
    : name_(std::move(name)), data_(std::move(data)) {
  const auto fail = [&](const std::string& what) {
    throw MaterialError(fmt::format("material '{}': stress map: {}", name_, what));
  };
  const auto& d = data_;
  const size_t n1 = d.e1.size(), n2 = d.e2.size();
  if (n1 < 2 || n2 < 2) fail("each strain axis needs at least two values");
  if (!strictly_increasing(d.e1) || !strictly_increasing(d.e2))
    fail("the strain axes must be strictly increasing");
  if (d.S11.size() != n1 * n2 || d.S22.size() != n1 * n2)
    fail(fmt::format("the stress tables need {} x {} values", n1, n2));
  const auto i0 = std::find(d.e1.begin(), d.e1.end(), 0.0);
  const auto j0 = std::find(d.e2.begin(), d.e2.end(), 0.0);
  if (i0 == d.e1.end() || j0 == d.e2.end())
    fail("the grid must hold zero strain (E11 = 0 and E22 = 0 among its values)");
  for (size_t j = 0; j < n2; ++j)
    for (size_t i = 0; i + 1 < n1; ++i)
      if (!(d.S11[j * n1 + i + 1] > d.S11[j * n1 + i]))
        fail(fmt::format("S11 must increase with E11 (at E22 = {}, E11 = {} to {})", d.e2[j],
                         d.e1[i], d.e1[i + 1]));
  for (size_t i = 0; i < n1; ++i)
    for (size_t j = 0; j + 1 < n2; ++j)
      if (!(d.S22[(j + 1) * n1 + i] > d.S22[j * n1 + i]))
        fail(fmt::format("S22 must increase with E22 (at E11 = {}, E22 = {} to {})", d.e1[i],
                         d.e2[j], d.e2[j + 1]));
  const size_t k0 =
      static_cast<size_t>(j0 - d.e2.begin()) * n1 + static_cast<size_t>(i0 - d.e1.begin());
  double smax = 0;
  for (size_t k = 0; k < n1 * n2; ++k)
    smax = std::max({smax, std::abs(d.S11[k]), std::abs(d.S22[k])});
  if (std::abs(d.S11[k0]) > 1e-9 * smax || std::abs(d.S22[k0]) > 1e-9 * smax)
    fail("the stress at zero strain must be zero (give a prestress in the section instead)");
  if (d.gamma.empty()) {
    if (!(d.G12 > 0)) fail("the shear modulus G12 must be positive");
  } else {
    if (d.gamma.size() != d.S12.size() || d.gamma.size() < 2)
      fail("the shear curve needs at least two points (gamma, S12)");
    if (d.gamma[0] != 0 || d.S12[0] != 0) fail("the shear curve must start at (0, 0)");
    if (!strictly_increasing(d.gamma)) fail("the shear curve's gamma must be strictly increasing");
    if (!strictly_increasing(d.S12)) fail("the shear curve's S12 must increase with gamma");
    shear_ = MonotoneCubic(d.gamma, d.S12);
  }
  S11_ = make_field(d.S11);
  S22_ = make_field(d.S22);
  // An unloading line no steeper than the map would rise above it below the turning point
  // (a cycle giving back more work than it took): each modulus at least the steepest slope of
  // its stress along its own strain at the grid points, where the map also extrapolates.
  for (int c = 0; c < 2; ++c) {
    const double K = d.unloading[c];
    if (K == 0) continue;
    if (!(K > 0)) fail(fmt::format("the unloading modulus must be positive (got {})", K));
    const auto& slopes = c == 0 ? S11_.fx : S22_.fy;
    const double steepest = *std::max_element(slopes.begin(), slopes.end());
    if (K < steepest)
      fail(fmt::format(
          "the {} unloading modulus {} is below the map's steepest slope d{}/d{} = "
          "{:.6g}: unloading must not be softer than loading",
          c == 0 ? "warp" : "fill", K, c == 0 ? "S11" : "S22", c == 0 ? "E11" : "E22", steepest));
  }
  SheetResponse r;
  evaluate(Vec3::Zero(), r);
  C0_ = r.C;
  if (!(C0_(0, 0) > 0) || !(C0_(1, 1) > 0) || !(C0_(2, 2) > 0))
    fail(
        fmt::format("the slopes at zero strain must be positive (dS11/dE11 = {}, dS22/dE22 = "
                    "{}, dS12/dgamma = {})",
                    C0_(0, 0), C0_(1, 1), C0_(2, 2)));
}

StressMapSheetLaw::Field StressMapSheetLaw::make_field(const std::vector<double>& values) const {
  const auto& e1 = data_.e1;
  const auto& e2 = data_.e2;
  const size_t n1 = e1.size(), n2 = e2.size();
  Field F;
  F.f = values;
  F.fx.resize(values.size());
  F.fy.resize(values.size());
  F.fxy.resize(values.size());
  std::vector<double> line;
  for (size_t j = 0; j < n2; ++j) {
    line.assign(values.begin() + static_cast<long>(j * n1),
                values.begin() + static_cast<long>((j + 1) * n1));
    const auto s = monotone_slopes(e1, line);
    std::copy(s.begin(), s.end(), F.fx.begin() + static_cast<long>(j * n1));
  }
  std::vector<double> col(n2), colx(n2);
  for (size_t i = 0; i < n1; ++i) {
    for (size_t j = 0; j < n2; ++j) col[j] = values[j * n1 + i], colx[j] = F.fx[j * n1 + i];
    const auto s = monotone_slopes(e2, col);
    const auto sx = monotone_slopes(e2, colx);
    for (size_t j = 0; j < n2; ++j) F.fy[j * n1 + i] = s[j], F.fxy[j * n1 + i] = sx[j];
  }
  return F;
}

double StressMapSheetLaw::shear(double gamma, double* dS) const {
  if (data_.gamma.empty()) {
    *dS = data_.G12;
    return data_.G12 * gamma;
  }
  // The curve for γ ≥ 0, odd in γ (a fabric shears alike both ways in its axes).
  const double s = shear_(std::abs(gamma), dS);
  return gamma < 0 ? -s : s;
}

void StressMapSheetLaw::evaluate(const Vec3& E, SheetResponse& out) const {
  const HermiteWeights wx = hermite_weights(data_.e1, E[0]);
  const HermiteWeights wy = hermite_weights(data_.e2, E[1]);
  const size_t n1 = data_.e1.size();
  // Corner a (x) and b (y) of the patch: node (i + a % 2, j + b % 2); a, b >= 2 are slopes.
  double s[2] = {0, 0}, sx[2] = {0, 0}, sy[2] = {0, 0};
  const Field* fields[2] = {&S11_, &S22_};
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      const size_t k = static_cast<size_t>(wy.i + b % 2) * n1 + static_cast<size_t>(wx.i + a % 2);
      const double w = wx.w[a] * wy.w[b], wdx = wx.dw[a] * wy.w[b], wdy = wx.w[a] * wy.dw[b];
      for (int c = 0; c < 2; ++c) {
        const Field& F = *fields[c];
        const double v = a < 2 ? (b < 2 ? F.f[k] : F.fy[k]) : (b < 2 ? F.fx[k] : F.fxy[k]);
        s[c] += w * v;
        sx[c] += wdx * v;
        sy[c] += wdy * v;
      }
    }
  }
  double G = 0;
  const double s12 = shear(E[2], &G);
  out.S = Vec3(s[0], s[1], s12);
  out.C << sx[0], sy[0], 0, sx[1], sy[1], 0, 0, 0, G;
  out.state = WrinkleState::kTaut;
  out.angle = 0;
}

void StressMapSheetLaw::evaluate(const Vec3& E, std::span<const double> h,
                                 SheetResponse& out) const {
  evaluate(E, out);
  if (h.empty()) return;
  // Below the largest strain reached in a direction, that direction's stress follows the line
  // of the unloading modulus from the map's value there (at the other strain as it is now).
  for (int c = 0; c < 2; ++c) {
    const double K = data_.unloading[c];
    if (!(K > 0) || !(h[c] > 0) || !(E[c] < h[c])) continue;
    Vec3 Et = E;
    Et[c] = h[c];
    SheetResponse turn;
    evaluate(Et, turn);
    out.S[c] = turn.S[c] - K * (h[c] - E[c]);
    out.C(c, c) = K;
    out.C(c, 1 - c) = turn.C(c, 1 - c);
  }
}

void StressMapSheetLaw::initial_state(std::span<double> h) const {
  for (double& v : h) v = 0;
}

void StressMapSheetLaw::update_state(const Vec3& E, std::span<double> h) const {
  h[0] = std::max(h[0], E[0]);
  h[1] = std::max(h[1], E[1]);
}

double StressMapSheetLaw::energy(const Vec3& E, std::span<const double> h) const {
  // Three-point Gauss on t in [0, 1] of S(t E) · E.
  static constexpr double kT[3] = {0.1127016653792583, 0.5, 0.8872983346207417};
  static constexpr double kW[3] = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  double W = 0;
  SheetResponse r;
  for (int q = 0; q < 3; ++q) {
    evaluate(kT[q] * E, h, r);
    W += kW[q] * r.S.dot(E);
  }
  return W;
}

}  // namespace velum
