// Enclosed-gas loads (`type: gas`, docs/inflatables.md) and their `gas_volume` /
// `gas_pressure` history entries: the keys (the chamber is checked by its set-up, Load::set_up).
#include <fmt/format.h>

#include <stdexcept>

#include "reader.hpp"

namespace velum::io::model_file {

void Reader::parse_gas_load(const Node& l, const std::string& p) {
  check_map(l, p, {"type", "elements", "initial_pressure", "ambient", "gamma", "amount", "origin"});
  GasLoad gas;
  bool ok = true;
  // elements: one set name or a list of them.
  std::vector<std::pair<std::string, Node>> sets;
  if (!has(l, "elements")) {
    require(l, "elements", p);
    ok = false;
  } else if (l["elements"].IsSequence()) {
    for (size_t k = 0; k < l["elements"].size(); ++k) {
      const Node s = l["elements"][k];
      if (s.IsScalar())
        sets.emplace_back(s.as<std::string>(), s);
      else
        error(s, item(sub(p, "elements"), k), "expected an element set name"), ok = false;
    }
  } else if (auto set = text(l, "elements", p, true)) {
    sets.emplace_back(*set, l["elements"]);
  } else {
    ok = false;
  }
  for (const auto& [set, at] : sets) {
    // A surface bounds one chamber: a second gas load on it would apply its pressure again.
    const std::string here =
        line_of(at) > 0 ? fmt::format("{} (line {})", p, line_of(at)) : std::string(p);
    if (auto [g, fresh] = gas_sets_.emplace(set, here); !fresh) {
      error(at, sub(p, "elements"),
            fmt::format("element set '{}' already bounds the gas of {}: a surface bounds one "
                        "chamber, and a second gas load would apply its pressure twice",
                        set, g->second));
      ok = false;
      continue;
    }
    auto sit = element_sets_.find(set);
    if (sit == element_sets_.end()) {
      if (mesh_ok_)
        error(at, sub(p, "elements"),
              fmt::format("undefined element set '{}'{}", set,
                          suggestion(set, keys_of(element_sets_))));
      ok = false;
      continue;
    }
    if (sit->second.dimension != 2) {
      error(at, sub(p, "elements"),
            fmt::format("gas acts on membranes; set '{}' holds cables", set));
      ok = false;
      continue;
    }
    for (int b : set_blocks_[set]) {
      GasLoad::Part part{b, std::vector<int>(static_cast<size_t>(in_.model.blocks[b]->size()))};
      for (size_t e = 0; e < part.elements.size(); ++e) part.elements[e] = static_cast<int>(e);
      gas.parts.push_back(std::move(part));
    }
  }
  auto p0 = positive(l, "initial_pressure", p, true, "the initial (absolute) pressure");
  auto pa = non_negative(l, "ambient", p, "the ambient pressure");
  auto gamma = positive(l, "gamma", p, false, "gamma");
  if (auto o = vec3(l, "origin", p, false)) gas.origin = *o;
  if (auto f = text(l, "amount", p, false)) {
    if (auto it = functions_.find(*f); it != functions_.end()) {
      gas.amount = it->second;
      // p = p0 m (V0/V)^gamma: no gas (m = 0) is no chamber, and the pressure's derivatives
      // divide by m. A ramp starts at 0; a constant or a table (held outside its points,
      // linear between them) stays positive where its values are.
      const TimeFunction& fn = in_.model.functions[static_cast<size_t>(it->second)];
      bool positive_amount = fn.kind != TimeFunction::Kind::kRamp;
      if (fn.kind == TimeFunction::Kind::kConstant) positive_amount = fn.value > 0;
      for (const auto& [t, v] : fn.points) positive_amount = positive_amount && v > 0;
      if (!positive_amount) {
        error(l["amount"], sub(p, "amount"),
              fmt::format("function '{}' is not positive at every time (a ramp starts at 0): "
                          "the amount of gas, relative to the initial one, must stay above 0",
                          *f));
        ok = false;
      }
    } else if (*f != "step") {
      auto names = keys_of(functions_);
      names.push_back("step");
      error(l["amount"], sub(p, "amount"),
            fmt::format("undefined function '{}'{}", *f, suggestion(*f, names)));
      ok = false;
    }
  }
  if (!p0) ok = false;
  if (!ok) return;
  gas.initial_pressure = *p0;
  gas.ambient = pa.value_or(0.0);
  gas.gamma = gamma.value_or(1.0);
  add_load(make_load(std::move(gas)), l["elements"], sub(p, "elements"));
}

bool Reader::parse_gas_history(const Node& e, const std::string& p, HistoryEntry& he) {
  if (!require(e, "load", p)) return false;
  auto k = integer(e["load"], sub(p, "load"), "the gas load index");
  if (!k) return false;
  const long n = static_cast<long>(in_.model.gases.size());
  if (*k < 0 || *k >= n) {
    error(e["load"], sub(p, "load"),
          n == 0 ? std::string("the model has no gas load (loads of type: gas)")
                 : fmt::format("no gas load {}: the model has {} (counted from 0, in the order "
                               "of the gas loads under loads)",
                               *k, n));
    return false;
  }
  he.load = static_cast<int>(*k);
  return true;
}

}  // namespace velum::io::model_file
