// *BOUNDARY, *AMPLITUDE, *SURFACE, *STEP with *STATIC / *DYNAMIC, *CLOAD, *DLOAD, *DSLOAD,
// *INITIAL CONDITIONS; the output requests through OutputRequests (output_requests.cpp).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include "model.hpp"

namespace velum::io::inp {
namespace {

struct StepReader {
  const Mesh& mesh;
  Diagnostics& diag;
  Step step;
  bool in_step = false, step_done = false;
  // *SURFACE: element ids with the sign a pressure takes on them (SPOS -1, SNEG +1).
  std::map<std::string, std::vector<std::pair<long, double>>> surfaces;
  // pressures by (element, 0 element-based | 1 surface-based): OP=MOD replaces
  std::map<std::pair<long, int>, Pressure> pressure_at;

  /// Node ids of a node id or node set name.
  std::optional<std::vector<long>> nodes(const Keyword& k, const DataLine& d) {
    const std::string& f = d.fields.empty() ? std::string() : d.fields[0];
    if (f.empty()) {
      diag.error(k, d, "field 1 (a node or node set) is missing");
      return std::nullopt;
    }
    if (std::isdigit(static_cast<unsigned char>(f[0]))) {
      auto id = diag.integer(k, d, 0);
      if (!id) return std::nullopt;
      if (!mesh.node_at.count(*id)) {
        diag.error(k, d, fmt::format("undefined node {}", *id));
        return std::nullopt;
      }
      return std::vector<long>{*id};
    }
    if (const Set* s = mesh.nset(f)) return s->ids;
    diag.error(k, d, fmt::format("undefined node set '{}'", f));
    return std::nullopt;
  }

  std::optional<std::vector<long>> elements(const Keyword& k, const DataLine& d) {
    const std::string& f = d.fields.empty() ? std::string() : d.fields[0];
    if (f.empty()) {
      diag.error(k, d, "field 1 (an element or element set) is missing");
      return std::nullopt;
    }
    if (std::isdigit(static_cast<unsigned char>(f[0]))) {
      auto id = diag.integer(k, d, 0);
      if (!id) return std::nullopt;
      if (!mesh.element_at.count(*id)) {
        diag.error(k, d, fmt::format("undefined element {}", *id));
        return std::nullopt;
      }
      return std::vector<long>{*id};
    }
    if (const Set* s = mesh.elset(f)) return s->ids;
    diag.error(k, d, fmt::format("undefined element set '{}'", f));
    return std::nullopt;
  }

  /// The AMPLITUDE= of a load or boundary block ("" when absent), checked to exist.
  std::string amplitude(const Keyword& k) {
    if (!k.has("AMPLITUDE")) return "";
    const std::string a = canonical(k.options.at("AMPLITUDE"));
    if (!step.amplitudes.count(a)) {
      diag.error(k, fmt::format("undefined amplitude '{}' (define it with *AMPLITUDE before "
                                "the step)",
                                k.options.at("AMPLITUDE")));
      return "";
    }
    return a;
  }

  // OP=MOD (the default) or OP=NEW (what the steps before applied of this kind is removed).
  void check_op(const Keyword& k, bool& fresh) {
    if (!k.has("OP")) return;
    const std::string op = canonical(k.options.at("OP"));
    if (op == "NEW" && in_step)
      fresh = true;
    else if (op != "MOD")
      diag.error(k, fmt::format("OP={}: MOD or NEW (NEW inside a step)", k.options.at("OP")));
  }

  void boundary(const Keyword& k) {
    diag.check_options(k, {"OP", "AMPLITUDE", "TYPE"});
    check_op(k, step.new_boundary);
    if (k.has("TYPE") && canonical(k.options.at("TYPE")) != "DISPLACEMENT")
      diag.error(k, fmt::format("TYPE={}: only displacements are supported", k.options.at("TYPE")));
    const std::string amp = amplitude(k);
    if (!in_step && k.has("AMPLITUDE"))
      diag.error(k, "AMPLITUDE= belongs to a *BOUNDARY inside the step");
    bool rotations = false;
    for (const auto& d : k.data) {
      auto ns = nodes(k, d);
      if (!ns) continue;
      std::vector<int> comps;
      double value = 0;
      const std::string second = d.fields.size() > 1 ? canonical(d.fields[1]) : "";
      if (!second.empty() && std::isalpha(static_cast<unsigned char>(second[0]))) {
        // ENCASTRE 1-6, PINNED 1-3, XSYMM 1 5 6, ..., XASYMM 2 3 4, ...: the translations
        static const std::map<std::string, std::vector<int>> kTypes = {
            {"ENCASTRE", {0, 1, 2}}, {"PINNED", {0, 1, 2}}, {"XSYMM", {0}},     {"YSYMM", {1}},
            {"ZSYMM", {2}},          {"XASYMM", {1, 2}},    {"YASYMM", {0, 2}}, {"ZASYMM", {0, 1}}};
        auto it = kTypes.find(second);
        if (it == kTypes.end() || d.fields.size() > 2) {
          diag.error(k, d,
                     fmt::format("unknown boundary type '{}' (ENCASTRE, PINNED, XSYMM, "
                                 "YSYMM, ZSYMM, XASYMM, YASYMM, ZASYMM)",
                                 d.fields[1]));
          continue;
        }
        comps = it->second;
        rotations = rotations || second != "PINNED";
      } else {
        auto first = diag.integer(k, d, 1);
        auto last = diag.integer(k, d, 2, first ? *first : 0L);
        auto v = diag.number(k, d, 3, 0.0);
        if (!first || !last || !v) continue;
        if (*first < 1 || *last < *first || *last > 6) {
          diag.error(k, d,
                     fmt::format("degrees of freedom {} to {}: Velum's nodes have the "
                                 "translations 1-3 (4-6, rotations, are ignored)",
                                 *first, *last));
          continue;
        }
        for (long c = *first; c <= std::min(*last, 3L); ++c)
          comps.push_back(static_cast<int>(c - 1));
        rotations = rotations || *last > 3;
        value = *v;
      }
      if (value != 0 && !in_step) {
        diag.error(k, d, "a non-zero displacement belongs to a *BOUNDARY inside the step");
        continue;
      }
      for (long n : *ns)
        for (int c : comps)
          step.constraints[{n, c}] = {value != 0 || !amp.empty(), value, amp,
                                      diag.where(d.file, d.line)};
    }
    if (rotations)
      diag.warn(k,
                "rotational degrees of freedom (4-6) are ignored: membranes and trusses have "
                "none");
  }

  void amplitude_block(const Keyword& k) {
    diag.check_options(k, {"NAME", "TIME", "DEFINITION", "VALUE"});
    auto name = diag.required(k, "NAME");
    if (!name) return;
    if (k.has("DEFINITION") && canonical(k.options.at("DEFINITION")) != "TABULAR") {
      diag.error(k, fmt::format("DEFINITION={} is not supported (TABULAR only)",
                                k.options.at("DEFINITION")));
      return;
    }
    if (k.has("VALUE") && canonical(k.options.at("VALUE")) != "RELATIVE") {
      diag.error(k, "only VALUE=RELATIVE is supported");
      return;
    }
    bool total = false;
    if (k.has("TIME")) {
      const std::string t = canonical(k.options.at("TIME"));
      if (t != "STEP TIME" && t != "TOTAL TIME") {
        diag.error(k, fmt::format("TIME={} is not supported (STEP TIME or TOTAL TIME)",
                                  k.options.at("TIME")));
        return;
      }
      total = t == "TOTAL TIME";
    }
    Amplitude a{*name, {}, total};
    std::vector<double> v;
    for (const auto& d : k.data)
      for (size_t i = 0; i < d.fields.size(); ++i)
        if (auto x = diag.number(k, d, i)) v.push_back(*x);
    if (v.empty() || v.size() % 2 != 0) {
      diag.error(k, fmt::format("expected pairs of time, value (got {} numbers)", v.size()));
      return;
    }
    for (size_t i = 0; i < v.size(); i += 2) {
      if (!a.points.empty() && v[i] <= a.points.back().first) {
        diag.error(k, fmt::format("the times must increase (pair {}: {} after {})", i / 2 + 1, v[i],
                                  a.points.back().first));
        return;
      }
      a.points.emplace_back(v[i], v[i + 1]);
    }
    const std::string key = canonical(*name);
    if (step.amplitudes.count(key)) {
      diag.error(k, fmt::format("amplitude '{}' is defined twice", *name));
      return;
    }
    step.amplitudes[key] = a;
  }

  void surface(const Keyword& k) {
    diag.check_options(k, {"NAME", "TYPE"});
    auto name = diag.required(k, "NAME");
    if (!name) return;
    if (k.has("TYPE") && canonical(k.options.at("TYPE")) != "ELEMENT") {
      diag.error(k, fmt::format("TYPE={}: only element-based surfaces (TYPE=ELEMENT) carry a "
                                "pressure",
                                k.options.at("TYPE")));
      return;
    }
    auto& s = surfaces[canonical(*name)];
    for (const auto& d : k.data) {
      auto es = elements(k, d);
      if (!es) continue;
      const std::string face = d.fields.size() > 1 ? canonical(d.fields[1]) : "SPOS";
      double sign = 0;
      if (face == "SPOS")
        sign = -1;  // a pressure pushes against the face's normal: -(g1 x g2)
      else if (face == "SNEG")
        sign = 1;
      else {
        diag.error(k, d, fmt::format("face '{}': membrane surfaces are SPOS or SNEG", d.fields[1]));
        continue;
      }
      for (long e : *es) s.emplace_back(e, sign);
    }
  }

  void cload(const Keyword& k) {
    diag.check_options(k, {"OP", "AMPLITUDE"});
    check_op(k, step.new_cloads);
    const std::string amp = amplitude(k);
    for (const auto& d : k.data) {
      auto ns = nodes(k, d);
      auto dof = diag.integer(k, d, 1);
      auto v = diag.number(k, d, 2);
      if (!ns || !dof || !v) continue;
      if (*dof < 1 || *dof > 3) {
        diag.error(k, d,
                   fmt::format("degree of freedom {}: Velum's nodes take forces 1-3 "
                               "(no moments)",
                               *dof));
        continue;
      }
      for (long n : *ns)
        step.loads[{n, static_cast<int>(*dof - 1)}] = {*v, amp, diag.where(d.file, d.line)};
    }
  }

  void pressure(const Keyword& k, long element, double value, const std::string& amp,
                const DataLine& d, int source) {
    if (mesh.elements[mesh.element_at.at(element)].type.rfind("cable", 0) == 0) {
      diag.error(k, d, fmt::format("element {} is a truss: pressure acts on membranes", element));
      return;
    }
    pressure_at[{element, source}] = {{element}, value, amp, diag.where(d.file, d.line)};
  }

  void dload(const Keyword& k) {
    diag.check_options(k, {"OP", "AMPLITUDE"});
    check_op(k, step.new_dloads);
    const std::string amp = amplitude(k);
    for (const auto& d : k.data) {
      auto es = elements(k, d);
      const std::string label = d.fields.size() > 1 ? canonical(d.fields[1]) : "";
      auto v = diag.number(k, d, 2);
      if (!es || !v) continue;
      if (label == "P") {
        if (d.fields.size() > 3) diag.error(k, d, "a pressure takes its magnitude only");
        for (long e : *es) pressure(k, e, -*v, amp, d, 0);
      } else if (label == "GRAV") {
        Vec3 n;
        bool ok = d.fields.size() == 6;
        for (int c = 0; ok && c < 3; ++c) {
          auto x = diag.number(k, d, static_cast<size_t>(3 + c));
          ok = x.has_value();
          if (ok) n[c] = *x;
        }
        if (!ok || n.norm() == 0) {
          diag.error(k, d,
                     "GRAV needs the magnitude and a non-zero direction: set, GRAV, g, "
                     "n1, n2, n3");
          continue;
        }
        if (es->size() != mesh.elements.size()) {
          diag.error(k, d,
                     "Velum's gravity acts on the whole model: give GRAV on a set of all "
                     "elements");
          continue;
        }
        step.gravity.push_back({*v * n.normalized(), amp, diag.where(d.file, d.line)});
      } else {
        diag.error(k, d,
                   fmt::format("load label '{}' is not supported (P: pressure; GRAV: "
                               "gravity on all elements)",
                               label));
      }
    }
  }

  void dsload(const Keyword& k) {
    diag.check_options(k, {"OP", "AMPLITUDE"});
    check_op(k, step.new_dsloads);
    const std::string amp = amplitude(k);
    for (const auto& d : k.data) {
      const std::string name = d.fields.empty() ? "" : canonical(d.fields[0]);
      auto it = surfaces.find(name);
      if (it == surfaces.end()) {
        diag.error(k, d,
                   fmt::format("undefined surface '{}' (define it with *SURFACE)",
                               d.fields.empty() ? "" : d.fields[0]));
        continue;
      }
      const std::string label = d.fields.size() > 1 ? canonical(d.fields[1]) : "";
      auto v = diag.number(k, d, 2);
      if (!v) continue;
      if (label != "P" || d.fields.size() > 3) {
        diag.error(k, d,
                   fmt::format("load label '{}' is not supported (P: a uniform pressure)", label));
        continue;
      }
      for (const auto& [e, sign] : it->second) pressure(k, e, sign * *v, amp, d, 1);
    }
  }

  void begin_step(const Keyword& k) {
    diag.check_options(k, {"NLGEOM", "INC", "AMPLITUDE", "NAME", "UNSYMM"});
    if (in_step) {
      diag.error(k, "a *STEP inside a step (no *END STEP before it)");
      return;
    }
    if (step_done) {  // the next step: the amplitudes go on, the rest is its own
      const auto amplitudes = step.amplitudes;
      done.push_back(std::move(step));
      step = Step{};
      step.amplitudes = amplitudes;
      pressure_at.clear();
      ramp_given = inc_given = procedure_seen = false;
    }
    in_step = true;
    step.present = true;
    step.file = k.file, step.line = k.line;
    if (k.has("NAME")) step.name = k.options.at("NAME");
    const std::string nl = k.has("NLGEOM") ? canonical(k.options.at("NLGEOM")) : "NO";
    if (nl != "" && nl != "YES")
      diag.warn(k,
                "the deck asks for a geometrically linear analysis (NLGEOM absent or NO); "
                "Velum is always geometrically nonlinear: results differ where rotations are "
                "not small");
    if (k.has("INC")) {
      const DataLine d{k.file, k.line, {k.options.at("INC")}};
      if (auto n = diag.integer(k, d, 0); n && *n > 0) step.max_steps = *n;
      inc_given = true;
    }
    if (k.has("AMPLITUDE")) {
      const std::string a = canonical(k.options.at("AMPLITUDE"));
      if (a == "STEP")
        step.ramp_default = false, ramp_given = true;
      else if (a == "RAMP")
        step.ramp_default = true, ramp_given = true;
      else
        diag.error(k, fmt::format("AMPLITUDE={}: RAMP or STEP", a));
    }
  }
  bool ramp_given = false, inc_given = false;
  std::vector<Step> done{};  // the steps read before this one

  void procedure(const Keyword& k) {
    const bool dynamic = k.name == "DYNAMIC";
    if (!in_step) {
      diag.error(k, "a procedure outside a *STEP");
      return;
    }
    if (procedure_seen) {
      diag.error(k, "the step has a procedure already");
      return;
    }
    procedure_seen = true;
    diag.check_options(k, dynamic ? std::vector<std::string>{"DIRECT", "ALPHA"}
                                  : std::vector<std::string>{"DIRECT", "RIKS"});
    step.dynamic = dynamic;
    step.direct = k.has("DIRECT");
    if (k.has("RIKS")) return riks(k);
    if (inc_given)
      diag.warn(k,
                "INC= (the maximum number of increments) has no counterpart: Velum takes "
                "the increments the step needs");
    if (dynamic && !ramp_given) step.ramp_default = false;
    if (dynamic && !ramp_given)
      diag.warn(k,
                "loads without an amplitude are applied at full strength at the start of a "
                "dynamic step (CalculiX's rule; give *STEP, AMPLITUDE=RAMP for a ramp)");
    if (dynamic && k.has("ALPHA")) {
      const DataLine d{k.file, k.line, {k.options.at("ALPHA")}};
      auto a = diag.number(k, d, 0);
      if (a && (*a < -1.0 / 3.0 || *a > 0))
        diag.error(k, fmt::format("ALPHA={} must lie in [-1/3, 0]", *a));
      else if (a)
        step.alpha = *a;
    }
    if (k.data.size() > 1) diag.error(k, "expected one data line");
    step.initial = step.period = step.max_inc = 1;  // without a data line
    step.min_inc = 1e-5;
    if (k.data.empty()) return;
    const DataLine& d = k.data[0];
    auto period = diag.number(k, d, 1, 1.0);
    if (!period) return;
    auto initial = diag.number(k, d, 0, *period);
    auto min_inc = diag.number(k, d, 2, std::min(*initial, 1e-5 * *period));
    auto max_inc = diag.number(k, d, 3, *period);
    if (!initial || !min_inc || !max_inc) return;
    if (*period <= 0 || *initial <= 0 || *initial > *period || *min_inc <= 0 ||
        *min_inc > *initial) {
      diag.error(k, d,
                 fmt::format("needs 0 < minimum ({}) <= initial increment ({}) <= period "
                             "({})",
                             *min_inc, *initial, *period));
      return;
    }
    step.initial = *initial, step.period = *period, step.min_inc = *min_inc;
    step.max_inc = *max_inc;
    if (*max_inc < *period && !step.direct)
      diag.warn(k, d,
                fmt::format("the maximum increment ({}) is not enforced: Velum's adaptive "
                            "steps grow while Newton converges easily",
                            *max_inc));
  }
  bool procedure_seen = false;
  OutputRequests requests{mesh, diag};

  // The step's pressures: one entry per (value, amplitude), elements in order.
  void group_pressures() {
    std::map<std::tuple<int, double, std::string>, size_t> group;
    for (const auto& [key, p] : pressure_at) {
      auto [it, fresh] =
          group.try_emplace({key.second, p.value, p.amplitude}, step.pressures.size());
      if (fresh) step.pressures.push_back({{}, p.value, p.amplitude, p.where});
      step.pressures[it->second].elements.push_back(key.first);
    }
  }

  // *INITIAL CONDITIONS, TYPE=STRESS: element or element set, then the stress components
  // in the material axes (a membrane S11, S22, S12; a truss S11): the sections' prestress.
  void initial_conditions(const Keyword& k) {
    diag.check_options(k, {"TYPE"});
    const std::string type = k.has("TYPE") ? canonical(k.options.at("TYPE")) : "";
    if (type != "STRESS") {
      diag.error(k, fmt::format("TYPE={} is not supported (Velum reads TYPE=STRESS, as the "
                                "sections' prestress)",
                                type.empty() ? "(none)" : type));
      return;
    }
    if (in_step) diag.error(k, "initial conditions are model data: give them before the *STEP");
    for (const auto& d : k.data) {
      auto es = elements(k, d);
      if (!es) continue;
      Vec3 S = Vec3::Zero();
      bool ok = true;
      for (size_t i = 1; i < d.fields.size() && ok; ++i) {
        auto v = diag.number(k, d, i, 0.0);
        ok = v.has_value();
        if (ok && i <= 3) S[static_cast<int>(i - 1)] = *v;
      }
      if (!ok) continue;
      for (long e : *es) {
        const bool truss = mesh.elements[mesh.element_at.at(e)].type.rfind("cable", 0) == 0;
        if (d.fields.size() > (truss ? 2u : 4u)) {
          diag.error(k, d,
                     fmt::format("element {} is a {}: its stress has {} (got {} values)", e,
                                 truss ? "truss" : "membrane",
                                 truss ? "one component, S11" : "three components, S11, S22, S12",
                                 d.fields.size() - 1));
          break;
        }
        step.initial_stress[e] = S;
      }
    }
  }

  // *STATIC, RIKS: initial arc length, period, minimum, maximum, maximum LPF, node, degree of
  // freedom, its displacement limit. The loads scale with the load proportionality factor
  // (Abaqus ignores their amplitudes): Velum's load parameter t through a linear function.
  void riks(const Keyword& k) {
    step.riks = true;
    step.initial = step.period = step.max_inc = 1;
    step.min_inc = 1e-5;
    if (k.data.size() > 1) diag.error(k, "expected one data line");
    if (k.data.empty()) {
      diag.warn(k, "no data line: the loads as given are reached (load proportionality factor 1)");
      return;
    }
    const DataLine& d = k.data[0];
    auto period = diag.number(k, d, 1, 1.0);
    if (!period) return;
    auto initial = diag.number(k, d, 0, *period);
    auto min_inc = diag.number(k, d, 2, std::min(*initial, 1e-5 * *period));
    auto max_inc = diag.number(k, d, 3, *period);
    auto lpf = diag.number(k, d, 4, 0.0);
    if (!initial || !min_inc || !max_inc || !lpf) return;
    if (*period <= 0 || *initial <= 0 || *initial > *period || *min_inc <= 0 ||
        *min_inc > *initial) {
      diag.error(k, d,
                 fmt::format("needs 0 < minimum ({}) <= initial arc length ({}) <= period ({})",
                             *min_inc, *initial, *period));
      return;
    }
    // Abaqus's first load increment is initial / period of the loads given.
    step.initial = *initial / *period, step.min_inc = *min_inc / *period;
    step.period = 1, step.max_inc = *max_inc / *period;
    if (*lpf > 0)
      step.max_lpf = *lpf;
    else
      diag.warn(k, d,
                "no maximum load proportionality factor (field 5): the run ends when the "
                "loads as given are reached (factor 1) or after the step's INC= increments");
    if (d.fields.size() > 5 && !d.fields[5].empty())
      diag.warn(k, d,
                "the displacement limit (fields 6-8) is not read: Velum's arc length ends at "
                "the maximum load proportionality factor or after INC= increments");
  }
};

}  // namespace

std::vector<Step> read_step(const std::vector<Keyword>& keywords, const Mesh& mesh,
                            std::vector<bool>& used, Diagnostics& diag) {
  StepReader r{mesh, diag, {}, false, false, {}, {}};
  for (size_t i = 0; i < keywords.size(); ++i) {
    const Keyword& k = keywords[i];
    const bool step_only = k.name == "CLOAD" || k.name == "DLOAD" || k.name == "DSLOAD" ||
                           k.name == "STATIC" || k.name == "DYNAMIC" || k.name == "END STEP";
    if (step_only && !r.in_step && k.name != "STATIC" && k.name != "DYNAMIC") {
      diag.error(k, "belongs inside a *STEP ... *END STEP");
      used[i] = true;
      continue;
    }
    if (k.name == "BOUNDARY")
      r.boundary(k);
    else if (k.name == "AMPLITUDE")
      r.amplitude_block(k);
    else if (k.name == "SURFACE")
      r.surface(k);
    else if (k.name == "STEP")
      r.begin_step(k);
    else if (k.name == "STATIC" || k.name == "DYNAMIC")
      r.procedure(k);
    else if (k.name == "CLOAD")
      r.cload(k);
    else if (k.name == "DLOAD")
      r.dload(k);
    else if (k.name == "DSLOAD")
      r.dsload(k);
    else if (k.name == "INITIAL CONDITIONS")
      r.initial_conditions(k);
    else if (r.requests.read(k)) {  // an output request: read
    } else if (k.name == "END STEP") {
      if (!r.procedure_seen) diag.error(k, "the step has no *STATIC or *DYNAMIC");
      r.group_pressures();
      r.pressure_at.clear();
      r.in_step = false;
      r.step_done = true;
    } else
      continue;
    used[i] = true;
  }
  if (r.in_step)
    diag.errors.push_back(
        fmt::format("{}: *STEP: no *END STEP", diag.where(r.step.file, r.step.line)));
  r.group_pressures();
  std::vector<Step> steps = std::move(r.done);
  steps.push_back(std::move(r.step));
  steps.front().history = std::move(r.requests.columns);
  return steps;
}

}  // namespace velum::io::inp
