// The sheet laws' parsers and their table (sheet_law_table.hpp).

#include "sheet_law_table.hpp"

#include "read_stress_map.hpp"

#include <fmt/format.h>

#include <algorithm>
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

constexpr SheetLawEntry kTable[] = {
    {"isotropic", isotropic}, {"orthotropic", orthotropic}, {"anisotropic", anisotropic},
    {"fibers", fibers},       {"matrix", matrix},           {"stress_map", parse_stress_map},
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
