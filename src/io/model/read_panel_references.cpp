// Reads mesh.panel_references: the stress-free flat panel of an element set, given per set so
// that a node on a seam has one reference in each panel it joins (a cutting pattern's round
// trip, docs/patterns.md). The set's elements measure strain from these positions; the node's
// own reference (mesh coordinates, or mesh.reference_positions) stays what the others see.

#include <fmt/format.h>

#include <set>

#include "reader.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io::model_file {

void Reader::parse_panel_references(const Node& list) {
  const std::string path = "mesh.panel_references";
  if (!list.IsSequence()) {
    error(list, path, "expected a list of {elements: set, positions: [[id, x, y, z], ...]}");
    return;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const Node e = list[i];
    const std::string p = item(path, i);
    if (!check_map(e, p, {"elements", "positions"})) continue;
    auto set = text(e, "elements", p, true);
    if (!set || !require(e, "positions", p)) continue;
    auto it = element_sets_.find(*set);
    if (it == element_sets_.end()) {
      error(e["elements"], sub(p, "elements"),
            fmt::format("undefined element set '{}'{}", *set,
                        suggestion(*set, keys_of(element_sets_))));
      continue;
    }
    if (it->second.dimension != 2) {
      error(e["elements"], sub(p, "elements"),
            fmt::format("element set '{}' is not a surface: a panel is one", *set));
      continue;
    }
    if (panel_refs_.count(*set)) {
      error(e["elements"], sub(p, "elements"),
            fmt::format("set '{}' is given a panel reference twice", *set));
      continue;
    }
    std::set<long> of_set;
    for (const auto& g : it->second.groups) of_set.insert(g.node_ids.begin(), g.node_ids.end());
    const Node ps = e["positions"];
    const std::string pp = sub(p, "positions");
    if (!ps.IsSequence()) {
      error(ps, pp, "expected a list of [id, x, y, z]");
      continue;
    }
    auto& refs = panel_refs_[*set];
    for (size_t k = 0; k < ps.size(); ++k) {
      const Node n = ps[k];
      const std::string q = item(pp, k);
      const auto row = node_row(n, q);
      if (!row) continue;
      const auto& [id, position] = *row;
      auto at = in_.model.node_index.find(id);
      if (at == in_.model.node_index.end() || !of_set.count(id)) {
        error(n, q, fmt::format("node {} is not a node of set '{}'", id, *set));
        continue;
      }
      if (!refs.emplace(at->second, position).second)
        error(n, q, fmt::format("node {} is given a reference position twice", id));
    }
  }
}

std::optional<NodePositions> Reader::panel_reference_of(const std::string& set,
                                                        const ElementSet& es, const Node& at,
                                                        const std::string& p) {
  auto it = panel_refs_.find(set);
  if (it == panel_refs_.end()) return std::nullopt;
  NodePositions X = in_.model.X;
  for (const auto& g : es.groups)
    for (long id : g.node_ids) {
      auto n = in_.model.node_index.find(id);
      if (n == in_.model.node_index.end()) continue;  // reported with the element
      auto r = it->second.find(n->second);
      if (r == it->second.end()) {
        error(at, p,
              fmt::format("set '{}' has a panel reference (mesh.panel_references) without node "
                          "{}: give every node of the panel",
                          set, id));
        return std::nullopt;
      }
      X.col(n->second) = r->second;
    }
  return X;
}

}  // namespace velum::io::model_file
