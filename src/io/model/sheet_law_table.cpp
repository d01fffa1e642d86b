// The sheet laws' parsers and their table (sheet_law_table.hpp).

#include "sheet_law_table.hpp"

#include "read_stress_map.hpp"

#include <fmt/format.h>

#include "velum/material/compressible_sheet_law.hpp"
#include "velum/material/incompressible_sheet_law.hpp"
#include "velum/material/plastic_sheet_law.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace velum::io::model_file {
namespace {

std::optional<SheetLaw> isotropic(ReaderContext& r, const Node& m, const std::string& name,
                                  const std::string& p) {
  r.check_map(m, p, {"type", "E", "nu", "density"});
  auto E = r.positive(m, "E", p, true, "Young's modulus E");
  auto nu = r.number(m, "nu", p, true);
  if (nu && (*nu <= -1 || *nu >= 0.5)) {
    r.error(m["nu"], ReaderContext::sub(p, "nu"),
            fmt::format("Poisson's ratio must lie in (-1, 0.5) for a stable isotropic "
                        "sheet (got {})",
                        *nu));
    nu.reset();
  }
  if (E && nu) return SheetLaw(PlaneStressLaw::isotropic(name, *E, *nu));
  return std::nullopt;
}

std::optional<SheetLaw> orthotropic_or_anisotropic(ReaderContext& r, const Node& m,
                                                   const std::string& name, const std::string& p,
                                                   bool aniso) {
  if (aniso)
    r.check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "eta1", "eta2", "density"});
  else
    r.check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "density"});
  AnisotropicConstants c;
  auto E1 = r.positive(m, "E1", p, true, "E1");
  auto E2 = r.positive(m, "E2", p, true, "E2");
  auto nu12 = r.number(m, "nu12", p, true);
  bool ok = E1 && E2 && nu12;
  if (r.has(m, "G12") && m["G12"].IsScalar() && m["G12"].Scalar() == "firt") {
    c.use_firt = true;
  } else if (auto G = r.positive(m, "G12", p, true, "the shear modulus G12")) {
    c.G12 = *G;
  } else {
    ok = false;
  }
  if (ok && nu12 && *nu12 < 0 && c.use_firt) {
    r.error(m["nu12"], ReaderContext::sub(p, "nu12"), "Firt's shear modulus needs nu12 >= 0");
    ok = false;
  }
  if (aniso) {
    auto e1 = r.number(m, "eta1", p, false), e2 = r.number(m, "eta2", p, false);
    c.eta1 = e1.value_or(0);
    c.eta2 = e2.value_or(0);
  }
  if (!ok) return std::nullopt;
  c.E1 = *E1, c.E2 = *E2, c.nu12 = *nu12;
  return SheetLaw(aniso ? PlaneStressLaw::anisotropic(name, c)
                        : PlaneStressLaw::orthotropic(name, c.E1, c.E2, c.nu12, c.G12, c.use_firt));
}

std::optional<SheetLaw> orthotropic(ReaderContext& r, const Node& m, const std::string& name,
                                    const std::string& p) {
  return orthotropic_or_anisotropic(r, m, name, p, false);
}

std::optional<SheetLaw> anisotropic(ReaderContext& r, const Node& m, const std::string& name,
                                    const std::string& p) {
  return orthotropic_or_anisotropic(r, m, name, p, true);
}

std::optional<SheetLaw> fibers(ReaderContext& r, const Node& m, const std::string& name,
                               const std::string& p) {
  r.check_map(m, p, {"type", "fibers", "density"});
  if (!r.require(m, "fibers", p)) return std::nullopt;
  const Node fs = m["fibers"];
  const std::string fp = ReaderContext::sub(p, "fibers");
  std::vector<FiberFamily> fams;
  bool ok = fs.IsSequence() && fs.size() > 0;
  if (!ok) r.error(fs, fp, "expected a list of {E, angle}");
  for (size_t i = 0; ok && i < fs.size(); ++i) {
    const std::string ip = ReaderContext::item(fp, i);
    if (!r.check_map(fs[i], ip, {"E", "angle"})) {
      ok = false;
      break;
    }
    auto E = r.positive(fs[i], "E", ip, true, "the fibre modulus E");
    auto a = r.number(fs[i], "angle", ip, true);
    if (!E || !a)
      ok = false;
    else
      fams.push_back({*E, *a});
  }
  if (ok) return SheetLaw(PlaneStressLaw::fibers(name, fams));
  return std::nullopt;
}

std::optional<SheetLaw> matrix(ReaderContext& r, const Node& m, const std::string& name,
                               const std::string& p) {
  r.check_map(m, p, {"type", "Q", "density"});
  if (!r.require(m, "Q", p)) return std::nullopt;
  const Node q = m["Q"];
  const std::string qp = ReaderContext::sub(p, "Q");
  Mat3 Q;
  bool ok = q.IsSequence() && q.size() == 3;
  for (size_t i = 0; ok && i < 3; ++i) {
    ok = q[i].IsSequence() && q[i].size() == 3;
    for (size_t j = 0; ok && j < 3; ++j) {
      auto v = r.number(q[i][j], qp);
      if (!v)
        ok = false;
      else
        Q(static_cast<int>(i), static_cast<int>(j)) = *v;
    }
  }
  if (!ok)
    r.error(q, qp, "expected a 3x3 matrix [[..], [..], [..]]");
  else if ((Q - Q.transpose()).cwiseAbs().maxCoeff() > 1e-12 * Q.cwiseAbs().maxCoeff())
    r.error(q, qp, "the stiffness matrix Q must be symmetric");
  else
    return SheetLaw(PlaneStressLaw::matrix(name, Q));
  return std::nullopt;
}

// Incompressible hyperelastic sheets (incompressible_sheet_law.hpp): each condition of
// stability reported on the key that breaks it.
std::optional<SheetLaw> neo_hookean(ReaderContext& r, const Node& m, const std::string& name,
                                    const std::string& p) {
  r.check_map(m, p, {"type", "mu", "nu", "density"});
  auto mu = r.positive(m, "mu", p, true, "the shear modulus mu");
  if (!r.has(m, "nu")) {
    if (mu) return SheetLaw(IncompressibleSheetLaw::neo_hookean(name, *mu));
    return std::nullopt;
  }
  // With Poisson's ratio the sheet is compressible (compressible_sheet_law.hpp).
  auto nu = r.number(m, "nu", p, true);
  if (nu && !(*nu > -1 && *nu < 0.5)) {
    r.error(m["nu"], ReaderContext::sub(p, "nu"),
            fmt::format("Poisson's ratio must lie in (-1, 0.5) for a compressible sheet (got "
                        "{}; leave nu out for the incompressible one)",
                        *nu));
    return std::nullopt;
  }
  if (mu && nu) return SheetLaw(CompressibleSheetLaw::neo_hookean(name, *mu, *nu));
  return std::nullopt;
}

std::optional<SheetLaw> mooney_rivlin(ReaderContext& r, const Node& m, const std::string& name,
                                      const std::string& p) {
  r.check_map(m, p, {"type", "C1", "C2", "density"});
  auto C1 = r.number(m, "C1", p, true), C2 = r.number(m, "C2", p, true);
  if (!C1 || !C2) return std::nullopt;
  if (!(*C1 + *C2 > 0)) {
    r.error(m["C1"], ReaderContext::sub(p, "C1"),
            fmt::format("C1 + C2 = {} must be positive (the small-strain shear modulus is "
                        "2 (C1 + C2))",
                        *C1 + *C2));
  } else if (!(*C1 >= 0)) {
    r.error(m["C1"], ReaderContext::sub(p, "C1"),
            fmt::format("C1 = {} must not be negative: the sheet would lose stability at a "
                        "uniaxial stretch of -C2/C1 = {:.4g} (stable at every stretch: C1 >= 0, "
                        "C2 >= 0, C1 + C2 > 0)",
                        *C1, -*C2 / *C1));
  } else if (!(*C2 >= 0)) {
    r.error(m["C2"], ReaderContext::sub(p, "C2"),
            fmt::format("C2 = {} must not be negative: the sheet would lose stability at an "
                        "equibiaxial stretch of sqrt(-C1/C2) = {:.4g} (stable at every "
                        "stretch: C1 >= 0, C2 >= 0, C1 + C2 > 0)",
                        *C2, std::sqrt(-*C1 / *C2)));
  } else {
    return SheetLaw(IncompressibleSheetLaw::mooney_rivlin(name, *C1, *C2));
  }
  return std::nullopt;
}

// Elastic-plastic sheet (plastic_sheet_law.hpp): von Mises, bilinear or tabulated hardening.
std::optional<SheetLaw> elastoplastic(ReaderContext& r, const Node& m, const std::string& name,
                                      const std::string& p) {
  r.check_map(
      m, p, {"type", "E", "nu", "yield_stress", "hardening_modulus", "hardening_curve", "density"});
  auto E = r.positive(m, "E", p, true, "Young's modulus E");
  auto nu = r.number(m, "nu", p, true);
  if (nu && (*nu <= -1 || *nu >= 0.5)) {
    r.error(m["nu"], ReaderContext::sub(p, "nu"),
            fmt::format("Poisson's ratio must lie in (-1, 0.5) (got {})", *nu));
    nu.reset();
  }
  const bool tabulated = r.has(m, "hardening_curve");
  if (tabulated && (r.has(m, "yield_stress") || r.has(m, "hardening_modulus"))) {
    r.error(m["hardening_curve"], ReaderContext::sub(p, "hardening_curve"),
            "give either yield_stress (and hardening_modulus) or hardening_curve, not both");
    return std::nullopt;
  }
  if (tabulated) {
    const Node c = m["hardening_curve"];
    const std::string cp = ReaderContext::sub(p, "hardening_curve");
    std::vector<std::pair<double, double>> curve;
    bool ok = c.IsSequence() && c.size() > 0;
    for (size_t i = 0; ok && i < c.size(); ++i) {
      ok = c[i].IsSequence() && c[i].size() == 2;
      if (!ok) break;
      auto a = r.number(c[i][0], ReaderContext::item(cp, i));
      auto s = r.number(c[i][1], ReaderContext::item(cp, i));
      if (!a || !s) return std::nullopt;
      curve.emplace_back(*a, *s);
    }
    if (!ok) {
      r.error(c, cp, "expected a list of [plastic strain, yield stress] points");
      return std::nullopt;
    }
    if (E && nu) return SheetLaw(PlasticSheetLaw::tabulated(name, *E, *nu, std::move(curve)));
    return std::nullopt;
  }
  auto sy = r.positive(m, "yield_stress", p, true, "the yield stress");
  auto H = r.non_negative(m, "hardening_modulus", p, "the hardening modulus");
  if (E && nu && sy) return SheetLaw(PlasticSheetLaw::bilinear(name, *E, *nu, *sy, H.value_or(0)));
  return std::nullopt;
}

constexpr SheetLawEntry kTable[] = {
    {"isotropic", isotropic},
    {"orthotropic", orthotropic},
    {"anisotropic", anisotropic},
    {"fibers", fibers},
    {"matrix", matrix},
    {"neo_hookean", neo_hookean},
    {"mooney_rivlin", mooney_rivlin},
    {"elastoplastic", elastoplastic},
    {"stress_map", parse_stress_map},
};

}  // namespace

std::span<const SheetLawEntry> sheet_law_table() {
  return kTable;
}

const SheetLawEntry* find_sheet_law(std::string_view type) {
  const auto it = std::find_if(std::begin(kTable), std::end(kTable),
                               [&](const SheetLawEntry& e) { return e.type == type; });
  return it == std::end(kTable) ? nullptr : &*it;
}

}  // namespace velum::io::model_file
