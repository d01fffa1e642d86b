// Reads materials: (membrane laws and cable laws, each with its density).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reader.hpp"

namespace velum::io::model_file {

void Reader::parse_materials(const Node& ms) {
  if (!ms.IsMap() || ms.size() == 0) {
    error(ms, "materials", "expected a mapping of name: {type: ..., ...}");
    return;
  }
  const std::vector<std::string> types = {"isotropic", "orthotropic", "anisotropic",
                                          "fibers",    "matrix",      "cable"};
  for (const auto& kv : ms) {
    const std::string name = kv.first.Scalar();
    const std::string p = sub("materials", name);
    const Node m = kv.second;
    MaterialDef def;
    materials_[name] = def;  // defined, even if invalid (no cascade of "undefined")
    if (!m.IsMap()) {
      error(m, p, "expected a mapping {type: ..., ...}");
      continue;
    }
    auto type = text(m, "type", p, true);
    if (!type) continue;
    def.type = *type;
    try {
      if (*type == "isotropic") {
        check_map(m, p, {"type", "E", "nu", "density"});
        auto E = positive(m, "E", p, true, "Young's modulus E");
        auto nu = number(m, "nu", p, true);
        if (nu && (*nu <= -1 || *nu >= 0.5)) {
          error(m["nu"], sub(p, "nu"),
                fmt::format("Poisson's ratio must lie in (-1, 0.5) for a stable isotropic "
                            "sheet (got {})",
                            *nu));
          nu.reset();
        }
        if (E && nu) def.law = PlaneStressLaw::isotropic(name, *E, *nu);
      } else if (*type == "orthotropic" || *type == "anisotropic") {
        const bool aniso = *type == "anisotropic";
        if (aniso)
          check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "eta1", "eta2", "density"});
        else
          check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "density"});
        AnisotropicConstants c;
        auto E1 = positive(m, "E1", p, true, "E1");
        auto E2 = positive(m, "E2", p, true, "E2");
        auto nu12 = number(m, "nu12", p, true);
        bool ok = E1 && E2 && nu12;
        if (has(m, "G12") && m["G12"].IsScalar() && m["G12"].Scalar() == "firt") {
          c.use_firt = true;
        } else if (auto G = positive(m, "G12", p, true, "the shear modulus G12")) {
          c.G12 = *G;
        } else {
          ok = false;
        }
        if (ok && nu12 && *nu12 < 0 && c.use_firt) {
          error(m["nu12"], sub(p, "nu12"), "Firt's shear modulus needs nu12 >= 0");
          ok = false;
        }
        if (aniso) {
          auto e1 = number(m, "eta1", p, false), e2 = number(m, "eta2", p, false);
          c.eta1 = e1.value_or(0);
          c.eta2 = e2.value_or(0);
        }
        if (ok) {
          c.E1 = *E1, c.E2 = *E2, c.nu12 = *nu12;
          def.law = aniso
                        ? PlaneStressLaw::anisotropic(name, c)
                        : PlaneStressLaw::orthotropic(name, c.E1, c.E2, c.nu12, c.G12, c.use_firt);
        }
      } else if (*type == "fibers") {
        check_map(m, p, {"type", "fibers", "density"});
        if (require(m, "fibers", p)) {
          const Node fs = m["fibers"];
          const std::string fp = sub(p, "fibers");
          std::vector<FiberFamily> fams;
          bool ok = fs.IsSequence() && fs.size() > 0;
          if (!ok) error(fs, fp, "expected a list of {E, angle}");
          for (size_t i = 0; ok && i < fs.size(); ++i) {
            const std::string ip = item(fp, i);
            if (!check_map(fs[i], ip, {"E", "angle"})) {
              ok = false;
              break;
            }
            auto E = positive(fs[i], "E", ip, true, "the fibre modulus E");
            auto a = number(fs[i], "angle", ip, true);
            if (!E || !a)
              ok = false;
            else
              fams.push_back({*E, *a});
          }
          if (ok) def.law = PlaneStressLaw::fibers(name, fams);
        }
      } else if (*type == "matrix") {
        check_map(m, p, {"type", "Q", "density"});
        if (require(m, "Q", p)) {
          const Node q = m["Q"];
          Mat3 Q;
          bool ok = q.IsSequence() && q.size() == 3;
          for (size_t i = 0; ok && i < 3; ++i) {
            ok = q[i].IsSequence() && q[i].size() == 3;
            for (size_t j = 0; ok && j < 3; ++j) {
              auto v = number(q[i][j], sub(p, "Q"));
              if (!v)
                ok = false;
              else
                Q(static_cast<int>(i), static_cast<int>(j)) = *v;
            }
          }
          if (!ok)
            error(q, sub(p, "Q"), "expected a 3x3 matrix [[..], [..], [..]]");
          else if ((Q - Q.transpose()).cwiseAbs().maxCoeff() > 1e-12 * Q.cwiseAbs().maxCoeff())
            error(q, sub(p, "Q"), "the stiffness matrix Q must be symmetric");
          else
            def.law = PlaneStressLaw::matrix(name, Q);
        }
      } else if (*type == "cable") {
        check_map(m, p, {"type", "E", "density", "compression"});
        def.cable = true;
        if (auto E = positive(m, "E", p, true, "Young's modulus E")) def.cable_law.E = *E;
        def.cable_law.compression = boolean(m, "compression", p).value_or(false);
      } else {
        error(m["type"], sub(p, "type"),
              fmt::format("unknown material type '{}'{}", *type, suggestion(*type, types)));
        continue;
      }
    } catch (const MaterialError& e) {
      error(m, p, e.what());
      continue;
    } catch (const std::invalid_argument& e) {
      error(m, p, e.what());
      continue;
    }
    auto rho = number(m, "density", p, true);
    if (rho && *rho < 0) {
      error(m["density"], sub(p, "density"),
            fmt::format("the density must not be negative (got {})", *rho));
      rho.reset();
    }
    if (rho) def.density = *rho;
    def.ok = rho.has_value() && (def.cable ? def.cable_law.E > 0 : def.law.has_value());
    materials_[name] = def;
    in_.materials.push_back({name, *type});
  }
}

}  // namespace velum::io::model_file
