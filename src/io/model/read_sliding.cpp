// Reads what a sliding_cable's section adds to its cable law (docs/cables.md): `friction` at
// the interior nodes, `reefing` (a time function: the line's length over its meshed length)
// and `cut_time` (the line released).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "reader.hpp"

namespace velum::io::model_file {
namespace {

// The least value a time function takes at any time (tables are held outside their points).
double least_value(const TimeFunction& f) {
  switch (f.kind) {
    case TimeFunction::Kind::kConstant:
      return f.value;
    case TimeFunction::Kind::kRamp:
      return 0;  // 0 at t <= 0
    case TimeFunction::Kind::kTable: {
      double m = f.points.front().second;
      for (const auto& [t, v] : f.points) m = std::min(m, v);
      return m;
    }
  }
  return 0;
}

}  // namespace

std::optional<SlidingCableSection> Reader::parse_sliding_section(const Node& s,
                                                                 const std::string& p,
                                                                 const ElementSet& es,
                                                                 const MaterialDef& md) {
  SlidingCableSection out;
  const char* keys[] = {"friction", "reefing", "cut_time"};
  const bool sliding = std::any_of(es.groups.begin(), es.groups.end(),
                                   [](const ElementGroup& g) { return g.type == "sliding_cable"; });
  bool ok = true;
  for (const char* key : keys)
    if (has(s, key) && !sliding) {
      error(s[key], sub(p, key), "applies to sliding_cable elements only");
      ok = false;
    }
  if (!ok) return std::nullopt;
  if (has(s, "friction")) {
    const auto mu = non_negative(s, "friction", p, "the friction coefficient");
    if (!mu) return std::nullopt;
    if (*mu > 0 && md.cable_law.compression) {
      error(s["friction"], sub(p, "friction"),
            "friction at the interior nodes needs a tension-only cable (the material has "
            "compression: true)");
      return std::nullopt;
    }
    out.friction = *mu;
  }
  if (has(s, "reefing")) {
    const std::string kp = sub(p, "reefing");
    const auto name = text(s, "reefing", p, true);
    if (!name) return std::nullopt;
    const auto it = functions_.find(*name);
    if (it == functions_.end()) {
      error(s["reefing"], kp,
            fmt::format("undefined function '{}'{}: the line's length over its meshed length "
                        "in time",
                        *name, suggestion(*name, keys_of(functions_))));
      return std::nullopt;
    }
    const TimeFunction& f = in_.model.functions[static_cast<size_t>(it->second)];
    if (const double least = least_value(f); !(least > 0)) {
      error(s["reefing"], kp,
            fmt::format("function '{}' takes the value {:.6g}, a line of no or negative length "
                        "(the value is the line's length over its meshed length): a reefing "
                        "function must stay > 0",
                        *name, least));
      return std::nullopt;
    }
    out.reefing = f;
  }
  if (has(s, "cut_time")) {
    const auto t = number(s, "cut_time", p, false);
    if (!t) return std::nullopt;
    out.cut_time = *t;
  }
  return out;
}

bool Reader::parse_slip_history(const Node& e, const std::string& p, HistoryEntry& he) {
  if (!locate_cable(e, p, he, "slip")) return false;
  const ElementBlock& b = *in_.model.blocks[static_cast<size_t>(he.block)];
  const long eid = in_.element_ids[static_cast<size_t>(he.block)][static_cast<size_t>(he.element)];
  if (!b.sliding()) {
    error(e["element"], sub(p, "element"),
          fmt::format("element {} is a {}: the quantity 'slip' is a sliding_cable's", eid,
                      b.type_name()));
    return false;
  }
  if (!require(e, "node", p)) return false;
  const auto id = integer(e["node"], sub(p, "node"), "node id (an interior node of the chain)");
  if (!id) return false;
  const auto chain = b.nodes(he.element);
  const auto it = in_.model.node_index.find(*id);
  const auto at = it == in_.model.node_index.end()
                      ? chain.end()
                      : std::find(chain.begin(), chain.end(), it->second);
  if (at == chain.end()) {
    error(e["node"], sub(p, "node"), fmt::format("node {} is not on sliding cable {}", *id, eid));
    return false;
  }
  const auto j = static_cast<int>(at - chain.begin());
  if (j == 0 || j + 1 == static_cast<int>(chain.size())) {
    error(e["node"], sub(p, "node"),
          fmt::format("node {} is an end of sliding cable {}, where its material is tied: "
                      "give an interior node",
                      *id, eid));
    return false;
  }
  he.chain_place = j;
  return true;
}

}  // namespace velum::io::model_file
