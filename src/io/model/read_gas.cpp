// Enclosed-gas loads (`type: gas`, docs/inflatables.md) and their `gas_volume` /
// `gas_pressure` history entries: the keys (the chamber is checked by its set-up, Load::set_up).
#include <fmt/format.h>

#include <limits>
#include <stdexcept>

#include "reader.hpp"

namespace velum::io::model_file {

std::optional<std::vector<GasLoad::Part>> Reader::gas_parts(const Node& l, const std::string& p,
                                                            bool walls) {
  std::vector<GasLoad::Part> parts;
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
    if (auto [g, fresh] = walls ? gas_sets_.emplace(set, here) : std::pair{gas_sets_.end(), true};
        !fresh) {
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
      parts.push_back(std::move(part));
    }
  }
  if (!ok) return std::nullopt;
  return parts;
}

void Reader::parse_gas_load(const Node& l, const std::string& p) {
  if (part_) {  // the chamber's closure and volume need the whole mesh at set-up
    error(l, p, "a gas load is not read with mesh.parts yet: run the model with its whole mesh");
    return;
  }
  check_map(l, p,
            {"type", "elements", "initial_pressure", "ambient", "gamma", "amount", "origin",
             "temperature", "gas_constant", "inflator", "vents", "leakage", "orifices"});
  GasLoad gas;
  bool ok = true;
  if (auto parts = gas_parts(l, p))
    gas.parts = std::move(*parts);
  else
    ok = false;
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
  if (!parse_gas_flow(l, p, gas)) ok = false;
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
  using Q = HistoryEntry::Quantity;
  const GasLoad& gas = in_.model.gases[static_cast<size_t>(*k)];
  const bool flow_quantity = he.quantity == Q::kGasTemperature || he.quantity == Q::kGasMass ||
                             he.quantity == Q::kGasMassFlow;
  if (flow_quantity && !gas.flows()) {
    error(e["quantity"], sub(p, "quantity"),
          fmt::format("gas load {} has no gas flow: give it temperature and gas_constant", *k));
    return false;
  }
  const char* kinds[] = {"inflator", "vent", "leakage", "orifice"};
  const size_t counts[] = {gas.inflators.size(), gas.vents.size(), gas.leaks.size(),
                           gas.orifices.size()};
  int given = 0;
  for (int i = 0; i < 4; ++i) {
    if (!has(e, kinds[i])) continue;
    ++given;
    if (he.quantity != Q::kGasMassFlow) {
      error(e[kinds[i]], sub(p, kinds[i]), "only a gas_mass_flow entry names a flow");
      return false;
    }
    auto j = integer(e[kinds[i]], sub(p, kinds[i]), "the flow's index");
    if (!j) return false;
    if (*j < 0 || *j >= static_cast<long>(counts[i])) {
      error(e[kinds[i]], sub(p, kinds[i]),
            fmt::format("gas load {} has {} {} flow(s) (counted from 0): no {}", *k, counts[i],
                        kinds[i], *j));
      return false;
    }
    he.flow = fmt::format("{}:{}", kinds[i], *j);
  }
  if (he.quantity == Q::kGasMassFlow && given != 1) {
    error(e, p,
          "a gas_mass_flow entry names one flow: inflator, vent, leakage or orifice (its "
          "index from 0)");
    return false;
  }
  return true;
}

}  // namespace velum::io::model_file

namespace velum::io::model_file {

int Reader::gas_function(const Node& map, const char* key, const std::string& p, bool required) {
  auto f = text(map, key, p, required);
  if (!f) return required ? -2 : -1;
  if (auto it = functions_.find(*f); it != functions_.end()) {
    gas_curves_.push_back({map[key], sub(p, key), it->second});
    return it->second;
  }
  if (*f == "step") return -1;
  auto names = keys_of(functions_);
  names.push_back("step");
  error(map[key], sub(p, key), fmt::format("undefined function '{}'{}", *f, suggestion(*f, names)));
  return -2;
}

bool Reader::parse_gas_flow(const Node& l, const std::string& p, GasLoad& gas) {
  const bool any = has(l, "temperature") || has(l, "gas_constant") || has(l, "inflator") ||
                   has(l, "vents") || has(l, "leakage") || has(l, "orifices");
  if (!any) return true;
  bool ok = true;
  auto T = positive(l, "temperature", p, true, "the gas temperature (absolute, > 0)");
  auto R = positive(l, "gas_constant", p, true, "the specific gas constant R");
  if (!T || !R) ok = false;
  if (has(l, "amount")) {
    error(l["amount"], sub(p, "amount"),
          "`amount` is the law without gas flow; with temperature and gas_constant the mass "
          "follows from the inflators, vents, leakage and orifices");
    ok = false;
  }
  gas.temperature = T.value_or(0), gas.gas_constant = R.value_or(0);
  // inflator: one map or a list of them.
  if (has(l, "inflator")) {
    const Node in = l["inflator"];
    const std::string ip = sub(p, "inflator");
    auto one = [&](const Node& m, const std::string& q) {
      if (!check_map(m, q, {"mass_flow", "temperature", "scale"})) return false;
      GasLoad::Inflator inf;
      const int f = gas_function(m, "mass_flow", q, true);
      if (f == -2) return false;
      inf.mass_flow = f;
      if (auto s = number(m, "scale", q, false)) inf.scale = *s;
      if (!require(m, "temperature", q)) return false;
      double value = 0;
      if (m["temperature"].IsScalar() && !YAML::convert<double>::decode(m["temperature"], value)) {
        // a name, not a number: a time function of the temperature
        const int tf = gas_function(m, "temperature", q, true);
        if (tf == -2) return false;
        inf.temperature_function = tf;
      } else {
        auto ti = positive(m, "temperature", q, true, "the inflator gas temperature (> 0)");
        if (!ti) return false;
        inf.temperature = *ti;
      }
      gas.inflators.push_back(inf);
      return true;
    };
    if (in.IsSequence()) {
      for (size_t k = 0; k < in.size(); ++k) ok = one(in[k], item(ip, k)) && ok;
    } else {
      ok = one(in, ip) && ok;
    }
  }
  if (has(l, "vents")) {
    const Node vs = l["vents"];
    if (!vs.IsSequence()) {
      error(vs, sub(p, "vents"), "expected a list of {area, discharge}");
      ok = false;
    } else {
      for (size_t k = 0; k < vs.size(); ++k) {
        const std::string q = item(sub(p, "vents"), k);
        if (!check_map(vs[k], q, {"area", "discharge", "open_pressure", "open_time"})) {
          ok = false;
          continue;
        }
        gas::Vent v;
        auto a = positive(vs[k], "area", q, true, "the vent area");
        auto cd = positive(vs[k], "discharge", q, false, "the discharge coefficient");
        if (cd && *cd > 1) {
          error(vs[k]["discharge"], sub(q, "discharge"),
                fmt::format("the discharge coefficient is {:g}: it lies in (0, 1]", *cd));
          cd.reset(), ok = false;
        }
        auto op = number(vs[k], "open_pressure", q, false);
        auto ot = number(vs[k], "open_time", q, false);
        if (!a || (has(vs[k], "discharge") && !cd)) {
          ok = false;
          continue;
        }
        v.area = *a, v.discharge = cd.value_or(1.0);
        if (op || ot) {  // opens at whichever comes first
          v.open_pressure = op.value_or(std::numeric_limits<double>::infinity());
          v.open_time = ot.value_or(std::numeric_limits<double>::infinity());
        }
        gas.vents.push_back(v);
      }
    }
  }
  if (has(l, "leakage")) {
    const Node ls = l["leakage"];
    if (!ls.IsSequence()) {
      error(ls, sub(p, "leakage"), "expected a list of {elements, permeability}");
      ok = false;
    } else {
      for (size_t k = 0; k < ls.size(); ++k) {
        const std::string q = item(sub(p, "leakage"), k);
        if (!check_map(ls[k], q, {"elements", "permeability", "quadratic"})) {
          ok = false;
          continue;
        }
        GasLoad::Leakage leak;
        auto parts = gas_parts(ls[k], q, false);
        auto kp = non_negative(ls[k], "permeability", q, "the permeability");
        auto b = non_negative(ls[k], "quadratic", q, "the quadratic coefficient");
        if (!require(ls[k], "permeability", q) || !parts || !kp ||
            (has(ls[k], "quadratic") && !b)) {
          ok = false;
          continue;
        }
        leak.parts = std::move(*parts);
        leak.permeability = *kp, leak.quadratic = b.value_or(0.0);
        gas.leaks.push_back(std::move(leak));
      }
    }
  }
  if (has(l, "orifices")) {
    const Node os = l["orifices"];
    if (!os.IsSequence()) {
      error(os, sub(p, "orifices"), "expected a list of {chamber, area, discharge}");
      ok = false;
    } else {
      for (size_t k = 0; k < os.size(); ++k) {
        const std::string q = item(sub(p, "orifices"), k);
        if (!check_map(os[k], q, {"chamber", "area", "discharge"}) ||
            !require(os[k], "chamber", q)) {
          ok = false;
          continue;
        }
        GasLoad::Orifice o;
        auto c = integer(os[k]["chamber"], sub(q, "chamber"), "the other chamber's gas load index");
        auto a = positive(os[k], "area", q, true, "the orifice area");
        auto cd = positive(os[k], "discharge", q, false, "the discharge coefficient");
        if (cd && *cd > 1) {
          error(os[k]["discharge"], sub(q, "discharge"),
                fmt::format("the discharge coefficient is {:g}: it lies in (0, 1]", *cd));
          ok = false;
          continue;
        }
        if (!c || !a || (has(os[k], "discharge") && !cd)) {
          ok = false;
          continue;
        }
        o.chamber = static_cast<int>(*c), o.area = *a, o.discharge = cd.value_or(1.0);
        gas.orifices.push_back(o);
        gas_orifices_.push_back({os[k]["chamber"], sub(q, "chamber"),
                                 static_cast<int>(in_.model.gases.size()), o.chamber});
      }
    }
  }
  return ok;
}

void Reader::check_gas_flow() {
  // Orifices join chambers with gas flow (other than themselves).
  const auto n = static_cast<int>(in_.model.gases.size());
  for (const auto& [at, path, self, other] : gas_orifices_) {
    if (other < 0 || other >= n)
      error(at, path,
            fmt::format("no gas load {}: the model has {} (counted from 0, in the order of the "
                        "gas loads under loads)",
                        other, n));
    else if (other == self)
      error(at, path, "an orifice joins two different chambers, not a chamber to itself");
    else if (!in_.model.gases[static_cast<size_t>(other)].flows())
      error(at, path,
            fmt::format("gas load {} has no gas flow (temperature and gas_constant): an orifice "
                        "joins chambers with gas flow",
                        other));
    else if (in_.model.gases[static_cast<size_t>(other)].gamma !=
                 in_.model.gases[static_cast<size_t>(self)].gamma ||
             in_.model.gases[static_cast<size_t>(other)].gas_constant !=
                 in_.model.gases[static_cast<size_t>(self)].gas_constant)
      error(at, path,
            "chambers joined by an orifice hold the same gas: give them the same gamma and "
            "gas_constant");
  }
  // The inflators' tables cover the run.
  const double t0 = 0, t1 = in_.analysis.time.t_end;
  for (const auto& [at, path, f] : gas_curves_) {
    const TimeFunction& fn = in_.model.functions[static_cast<size_t>(f)];
    if (fn.kind != TimeFunction::Kind::kTable || fn.points.empty()) continue;
    if (fn.points.front().first > t0 || fn.points.back().first < t1)
      error(at, path,
            fmt::format("the table '{}' runs from t = {:g} to {:g}, but the run goes from {:g} "
                        "to {:g}: an inflator's curve must cover the run",
                        fn.name, fn.points.front().first, fn.points.back().first, t0, t1));
  }
}

}  // namespace velum::io::model_file
