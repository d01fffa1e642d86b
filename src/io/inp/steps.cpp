// Several *STEPs as Velum's `steps:` (docs/inp-import.md): Abaqus propagates what a step does
// not redefine, held at its value at the end of the step before; a load redefined under the
// default ramp goes from that value to the new one over the step; OP=NEW removes what the
// steps before applied.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "model.hpp"

namespace velum::io::inp {

double Amplitude::at(double t) const {
  if (points.empty()) return 1;
  if (t <= points.front().first) return points.front().second;
  for (size_t i = 1; i < points.size(); ++i)
    if (t <= points[i].first) {
      const auto& [t0, v0] = points[i - 1];
      const auto& [t1, v1] = points[i];
      return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
    }
  return points.back().second;
}

namespace {

// The factor an item's amplitude has reached at the end of a step that started at `start`.
double end_factor(const Step& st, const std::string& amp, double start) {
  // Held, continued from where it was ("=from:"), ramped or stepped: at full value at the end.
  if (amp.empty() || amp[0] == '=') return 1;
  const Amplitude& a = st.amplitudes.at(amp);
  return a.at(a.total_time ? start + st.period : st.period);
}

}  // namespace

std::vector<Step> complete_steps(const std::vector<Step>& steps, Diagnostics& diag) {
  std::vector<Step> out;
  if (steps.empty()) return out;
  out.push_back(steps.front());
  double start = 0;
  for (size_t k = 1; k < steps.size(); ++k) {
    const Step& before = out.back();  // complete
    const Step& given = steps[k];
    Step st = given;  // its procedure, amplitudes, what it gives
    st.constraints.clear();
    st.loads.clear();
    st.held_loads.clear();
    st.pressures.clear();
    st.gravity.clear();
    // ---- boundary: held at the end values, then the step's own ----
    if (!given.new_boundary)
      for (const auto& [key, c] : before.constraints) {
        Constraint h = c;
        if (c.prescribed)
          h.value = c.value * end_factor(before, c.amplitude, start), h.amplitude = "=held";
        st.constraints[key] = h;
      }
    for (const auto& [key, c] : given.constraints) {
      Constraint n = c;
      auto held = st.constraints.find(key);
      const double from =
          held != st.constraints.end() && held->second.prescribed ? held->second.value : 0;
      if (n.prescribed && n.amplitude.empty() && given.ramp_default && from != 0) {
        // From `from` to the new value over the step: a ramp of the change on the held value
        // needs one motion per node, so it is written by the writer as value × a table from
        // from/value to 1 (the components must keep their ratio: checked there).
        n.amplitude = fmt::format("=from:{}", from);
      }
      st.constraints[key] = n;
    }
    // ---- point loads ----
    std::map<std::pair<long, int>, double> held_value;
    if (!given.new_cloads) {
      for (const auto& [key, l] : before.loads)
        held_value[key] += l.value * end_factor(before, l.amplitude, start);
      for (const auto& [key, l] : before.held_loads) held_value[key] += l.value;
    }
    for (const auto& [key, l] : given.loads) {
      const double v0 = held_value.count(key) ? held_value[key] : 0;
      if (l.amplitude.empty() && given.ramp_default) {  // from v0 to the new value
        if (v0 != 0) st.held_loads.push_back({key, {v0, "=held", l.where}});
        st.loads[key] = {l.value - v0, "", l.where};
      } else {
        st.loads[key] = l;
      }
      held_value.erase(key);
    }
    for (const auto& [key, v] : held_value)
      if (v != 0) st.held_loads.push_back({key, {v, "=held", ""}});
    // ---- pressures: held per element (OP=NEW on *DLOAD or *DSLOAD removes them all) ----
    std::map<std::pair<long, int>, std::pair<double, std::string>> pressure;  // value, where
    for (const auto& p : before.pressures) {
      const double f = end_factor(before, p.amplitude, start);
      for (long e : p.elements)
        pressure[{e, 0}].first += p.value * f, pressure[{e, 0}].second = p.where;
    }
    if (given.new_dloads || given.new_dsloads) pressure.clear();
    for (const auto& p : given.pressures) {
      if (p.amplitude.empty() && given.ramp_default) {
        // from each element's held value to the new one: grouped by the held value
        std::map<double, std::vector<long>> by_held;
        for (long e : p.elements) {
          auto it = pressure.find({e, 0});
          by_held[it == pressure.end() ? 0.0 : it->second.first].push_back(e);
          if (it != pressure.end()) pressure.erase(it);
        }
        for (const auto& [v0, els] : by_held) {
          if (v0 != 0) st.pressures.push_back({els, v0, "=held", p.where});
          st.pressures.push_back({els, p.value - v0, "", p.where});
        }
      } else {
        for (long e : p.elements) pressure.erase({e, 0});
        st.pressures.push_back(p);
      }
    }
    std::map<double, std::vector<long>> held_groups;
    std::map<double, std::string> held_where;
    for (const auto& [key, vw] : pressure)
      if (vw.first != 0)
        held_groups[vw.first].push_back(key.first), held_where[vw.first] = vw.second;
    for (const auto& [v, els] : held_groups)
      st.pressures.push_back({els, v, "=held", held_where[v]});
    // ---- gravity: held, or the step's own ----
    if (given.gravity.empty() && !given.new_dloads)
      for (const auto& g : before.gravity)
        st.gravity.push_back(
            {g.acceleration * end_factor(before, g.amplitude, start), "=held", g.where});
    for (const auto& g : given.gravity) st.gravity.push_back(g);
    start += before.period;
    if (st.riks)
      diag.errors.push_back(
          fmt::format("{}: *STATIC, RIKS: in a deck of several steps (Velum's analysis.path is not "
                      "available in steps: give the arc-length step a deck of its own)",
                      diag.where(st.file, st.line)));
    out.push_back(std::move(st));
  }
  if (out.front().riks)
    diag.errors.push_back(fmt::format(
        "{}: *STATIC, RIKS: in a deck of several steps (Velum's analysis.path is not available "
        "in steps: give the arc-length step a deck of its own)",
        diag.where(out.front().file, out.front().line)));
  return out;
}

}  // namespace velum::io::inp
