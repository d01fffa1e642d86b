// The output requests of a deck as history columns (docs/inp-import.md): *NODE PRINT, *NODE
// OUTPUT after *OUTPUT, HISTORY (or alone, as CalculiX writes it) and *ENERGY OUTPUT. *OUTPUT,
// FIELD sets what a *NODE OUTPUT after it is: a field, which Velum's frames carry anyway.

#include <fmt/format.h>

#include <algorithm>

#include "model.hpp"

namespace velum::io::inp {

bool OutputRequests::read(const Keyword& k) {
  if (k.name == "OUTPUT")
    output(k);
  else if (k.name == "NODE PRINT" || k.name == "NODE OUTPUT")
    node_output(k);
  else if (k.name == "ENERGY OUTPUT")
    energy_output(k);
  else
    return false;
  return true;
}

void OutputRequests::column(HistoryColumn c) {
  if (names_.insert(c.name).second) columns.push_back(std::move(c));
}

void OutputRequests::output(const Keyword& k) {
  diag_.check_options(k, {"HISTORY", "FIELD", "FREQUENCY", "TIME INTERVAL", "NUMBER INTERVAL",
                          "VARIABLE", "TIME POINTS", "OP"});
  field_output_ = k.has("FIELD") && !k.has("HISTORY");
  if (field_output_)
    diag_.warn(k, "field output: Velum writes every field in its frames (fields: true)");
}

void OutputRequests::node_output(const Keyword& k) {
  if (k.name == "NODE OUTPUT" && field_output_) {
    diag_.warn(k, "field output: Velum writes every field in its frames (fields: true)");
    return;
  }
  std::vector<long> nodes;
  std::string set;
  if (k.has("NSET")) {
    const Set* s = mesh_.nset(k.options.at("NSET"));
    if (!s) {
      diag_.error(k, fmt::format("undefined node set '{}'", k.options.at("NSET")));
      return;
    }
    nodes = s->ids, set = s->name;
  } else {
    for (const auto& n : mesh_.nodes) nodes.push_back(n.id);
    set = "ALL";
  }
  if (nodes.size() > kMaxNodeColumns)
    diag_.warn(k, fmt::format("the set has {} nodes: history columns of the first {} only "
                              "(request a smaller set)",
                              nodes.size(), kMaxNodeColumns));
  const std::string where = diag_.where(k.file, k.line);
  for (const auto& d : k.data)
    for (const auto& f : d.fields) {
      const std::string v = canonical(f);
      if (v.empty()) continue;
      // U, U1-U3; V, V1-V3; COORD, COORD1-3; RF, RF1-RF3 (summed over the set)
      std::string base = v, quantity;
      int only = -1;
      if (!v.empty() && v.back() >= '1' && v.back() <= '3' && v.size() > 1) {
        base = v.substr(0, v.size() - 1);
        only = v.back() - '1';
      }
      if (base == "U")
        quantity = "displacement";
      else if (base == "V")
        quantity = "velocity";
      else if (base == "COORD")
        quantity = "position";
      else if (base == "RF")
        quantity = "reaction";
      if (quantity.empty() || (only >= 0 && base == v)) {
        diag_.warn(k, d,
                   fmt::format("output variable {} is not read (Velum's history: U, V, "
                               "COORD, RF and their components)",
                               f));
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        if (only >= 0 && c != only) continue;
        if (quantity == "reaction") {
          const bool one = nodes.size() == 1;
          column({fmt::format("RF{}_{}", c + 1, one ? std::to_string(nodes[0]) : set), quantity, 0,
                  one ? "" : set, one ? nodes[0] : 0, c, where});
          continue;
        }
        for (size_t i = 0; i < std::min(nodes.size(), kMaxNodeColumns); ++i)
          column(
              {fmt::format("{}{}_{}", base, c + 1, nodes[i]), quantity, nodes[i], "", 0, c, where});
      }
    }
}

void OutputRequests::energy_output(const Keyword& k) {
  if (field_output_) return;
  static const std::map<std::string, std::string> kEnergy = {{"ALLKE", "kinetic_energy"},
                                                             {"ALLSE", "strain_energy"},
                                                             {"ALLIE", "strain_energy"},
                                                             {"ALLWK", "external_work"}};
  const std::string where = diag_.where(k.file, k.line);
  bool any = false;
  for (const auto& d : k.data)
    for (const auto& f : d.fields) {
      const std::string v = canonical(f);
      if (v.empty()) continue;
      any = true;
      if (auto it = kEnergy.find(v); it != kEnergy.end())
        column({v, it->second, 0, "", 0, -1, where});
      else
        diag_.warn(k, d, fmt::format("energy {} is not read (Velum's: ALLKE, ALLSE, ALLWK)", f));
    }
  if (!any)  // no variables: the whole model's energies
    for (const char* v : {"ALLKE", "ALLSE", "ALLWK"})
      column({v, kEnergy.at(v), 0, "", 0, -1, where});
}

}  // namespace velum::io::inp
