// Reads materials: (membrane laws, parsed by the table of sheet_law_table.hpp, and cable
// laws, each with its density).

#include <fmt/format.h>

#include <string>
#include <vector>

#include "reader.hpp"
#include "sheet_law_table.hpp"

namespace velum::io::model_file {

void Reader::parse_materials(const Node& ms) {
  if (!ms.IsMap() || ms.size() == 0) {
    error(ms, "materials", "expected a mapping of name: {type: ..., ...}");
    return;
  }
  std::vector<std::string> types;  // every `type:`, for the suggestion
  for (const auto& e : sheet_law_table()) types.emplace_back(e.type);
  types.emplace_back("cable");
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
      if (const SheetLawEntry* law = find_sheet_law(*type)) {
        def.law = law->parse(*this, m, name, p);
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
