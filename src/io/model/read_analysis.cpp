// Reads analysis: (type, integrator, time, Newton, damping, linear solver) and output:.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reader.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::io::model_file {
namespace {

bool valid_utf8(std::string_view s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    const size_t more = c < 0x80             ? 0
                        : (c & 0xE0) == 0xC0 ? 1
                        : (c & 0xF0) == 0xE0 ? 2
                        : (c & 0xF8) == 0xF0 ? 3
                                             : 4;
    if (more == 4 || s.size() - i <= more) return false;
    for (size_t k = 1; k <= more; ++k)
      if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
    i += more + 1;
  }
  return true;
}

/// Why `name` cannot head a history.csv column (read by spreadsheets and ParaView's CSV
/// reader, which split on commas, honour quotes and take the first line as the header).
std::optional<std::string> bad_column_name(const std::string& name) {
  if (name.empty()) return "a column name must not be empty";
  if (name.size() > kMaxHistoryNameBytes)
    return fmt::format("a column name has at most {} bytes (got {})", kMaxHistoryNameBytes,
                       name.size());
  if (!valid_utf8(name)) return "a column name must be valid UTF-8";
  for (char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return "a column name must not hold control characters (line breaks, tabs)";
  if (name.find_first_of(",\"'") != std::string::npos)
    return "a column name must not hold commas or quotes";
  if (name.front() == ' ' || name.back() == ' ')
    return "a column name must not begin or end with a space";
  if (name == "time") return "'time' is the first column already; choose another name";
  return std::nullopt;
}

}  // namespace

// Central difference's step: analysis.integrator's safety, stable_step and mass_scaling
// (docs/model-format.md).
void Reader::parse_explicit_step(const Node& in, const std::string& p) {
  ExplicitStepSettings& x = in_.analysis.explicit_step;
  const bool central = in_.analysis.scheme == "central-difference";
  for (const char* key : {"safety", "stable_step", "mass_scaling"})
    if (has(in, key) && !central)
      error(in[key], sub(p, key),
            fmt::format("{} is a setting of central-difference's step (scheme: "
                        "central-difference)",
                        key));
  if (!central) return;
  if (auto v = positive(in, "safety", p, false, "the safety factor")) {
    if (*v > 1)
      error(in["safety"], sub(p, "safety"),
            fmt::format("safety is the fraction of the stable step taken, in (0, 1] (got {})", *v));
    else
      x.safety = *v;
  }
  if (auto v = text(in, "stable_step", p, false)) {
    if (*v == "current" || *v == "start")
      x.from_current_state = *v == "current";
    else
      error(in["stable_step"], sub(p, "stable_step"),
            fmt::format("stable_step is 'current' (estimated again from the current state at "
                        "every check) or 'start' (got '{}')",
                        *v));
  }
  if (has(in, "mass_scaling")) {
    const Node m = in["mass_scaling"];
    const std::string q = sub(p, "mass_scaling");
    if (check_map(m, q, {"target_step"}))
      if (auto h = positive(m, "target_step", q, true, "the step mass scaling reaches"))
        x.target_step = *h;
  }
}

void Reader::parse_analysis(const Node& a) {
  if (!check_map(a, "analysis",
                 {"type", "integrator", "time", "newton", "damping", "linear_solver", "relaxation",
                  "predictor", "path", "petsc_options", "partition", "form_finding"}))
    return;
  AnalysisSettings& s = in_.analysis;
  // (sections are read before the analysis; analysis.newton.max_iterations overrides)
  if (wrinkles_) s.newton.max_iterations = kWrinklingMaxIterations;
  if (auto t = text(a, "type", "analysis", false)) {
    const AnalysisTypeInfo* found = nullptr;
    std::vector<std::string> names;
    for (const AnalysisTypeInfo& i : kAnalysisTypes) {
      names.emplace_back(i.name);
      if (*t == i.name) found = &i;
    }
    if (found)
      s.type = found->type;
    else
      error(a["type"], "analysis.type",
            fmt::format("unknown analysis type '{}'{}", *t, suggestion(*t, names)));
  }
  if (has(a, "form_finding")) {
    const Node f = a["form_finding"];
    const std::string p = "analysis.form_finding";
    if (s.type != AnalysisSettings::Type::kFormFinding)
      error(f, p, "form_finding settings need analysis.type: form_finding");
    if (check_map(f, p, {"stiffness", "tolerance", "max_updates", "max_seconds"})) {
      if (auto v = positive(f, "max_seconds", p, false, "the time budget of a load level"))
        s.form_finding.max_seconds = *v;
      if (auto v = positive(f, "stiffness", p, false, "the stabilizing stiffness"))
        s.form_finding.stiffness = *v;
      if (auto v = positive(f, "tolerance", p, false, "the tolerance")) {
        if (*v >= 1)
          error(f["tolerance"], sub(p, "tolerance"),
                fmt::format("tolerance is a residual relative to the force scale, below 1 (got {})",
                            *v));
        else
          s.form_finding.tolerance = *v;
      }
      if (has(f, "max_updates")) {
        if (auto n = integer(f["max_updates"], sub(p, "max_updates"), "a count")) {
          if (*n < 1 || *n > 1000000L)
            error(f["max_updates"], sub(p, "max_updates"),
                  fmt::format("max_updates must lie in [1, 1e6] (got {})", *n));
          else
            s.form_finding.max_updates = static_cast<int>(*n);
        }
      }
    }
  }
  if (has(a, "relaxation")) {
    const Node r = a["relaxation"];
    const std::string p = "analysis.relaxation";
    if (s.type != AnalysisSettings::Type::kRelaxation)
      error(r, p, "relaxation settings need analysis.type: relaxation");
    if (check_map(r, p, {"newton_switch", "max_iterations", "max_seconds"})) {
      if (auto v = positive(r, "max_seconds", p, false, "the time budget of a load level"))
        s.relaxation.max_seconds = *v;
      if (auto v = positive(r, "newton_switch", p, false, "the Newton switch")) {
        if (*v >= 1)
          error(r["newton_switch"], sub(p, "newton_switch"),
                fmt::format("newton_switch is a residual relative to the force scale, below 1 "
                            "(got {})",
                            *v));
        else
          s.relaxation.newton_switch = *v;
      }
      if (has(r, "max_iterations")) {
        if (auto n = integer(r["max_iterations"], sub(p, "max_iterations"), "a count")) {
          if (*n < 1 || *n > 1000000000L)
            error(r["max_iterations"], sub(p, "max_iterations"),
                  fmt::format("max_iterations must lie in [1, 1e9] (got {})", *n));
          else
            s.relaxation.max_iterations = *n;
        }
      }
    }
  }
  if (has(a, "integrator")) {
    const Node in = a["integrator"];
    const std::string p = "analysis.integrator";
    if (check_map(in, p,
                  {"scheme", "rho_inf", "alpha", "beta", "gamma", "safety", "stable_step",
                   "mass_scaling"})) {
      if (auto sc = text(in, "scheme", p, false)) {
        const std::vector<std::string> schemes = {"newmark", "hht", "generalized-alpha",
                                                  "central-difference"};
        if (std::find(schemes.begin(), schemes.end(), *sc) == schemes.end())
          error(in["scheme"], sub(p, "scheme"),
                fmt::format("unknown scheme '{}'{}", *sc, suggestion(*sc, schemes)));
        else
          s.scheme = *sc;
        if (*sc == "central-difference" && s.equilibrium())
          error(in["scheme"], sub(p, "scheme"), "central-difference needs type: dynamic");
      }
      if (auto r = number(in, "rho_inf", p, false)) {
        if (*r < 0 || *r > 1)
          error(in["rho_inf"], sub(p, "rho_inf"),
                fmt::format("rho_inf must lie in [0, 1] (got {})", *r));
        else
          s.rho_inf = *r;
      }
      if (auto al = number(in, "alpha", p, false)) {
        if (*al < 0 || *al > 1.0 / 3.0)
          error(in["alpha"], sub(p, "alpha"),
                fmt::format("the HHT alpha must lie in [0, 1/3] (got {})", *al));
        else
          s.hht_alpha = *al;
      }
      parse_explicit_step(in, p);
      if (auto b = positive(in, "beta", p, false, "the Newmark beta")) s.newmark_beta = *b;
      if (auto g = number(in, "gamma", p, false)) {
        if (*g < 0.5)
          error(in["gamma"], sub(p, "gamma"),
                fmt::format("the Newmark gamma must be at least 0.5 (got {})", *g));
        else
          s.newmark_gamma = *g;
      }
    }
  }
  if (require(a, "time", "analysis")) {
    const Node t = a["time"];
    const std::string p = "analysis.time";
    if (check_map(t, p, {"end", "step", "min_step", "adaptive"})) {
      auto end = positive(t, "end", p, true, "the end time");
      auto step = positive(t, "step", p, true, "the time step");
      auto min_step = positive(t, "min_step", p, false, "the smallest time step");
      if (end) s.time.t_end = *end;
      if (step) s.time.step = *step;
      if (min_step)
        s.time.min_step = *min_step;
      else if (step)
        s.time.min_step = std::min(s.time.min_step, *step);
      if (step && min_step && *min_step > *step)
        error(t["min_step"], sub(p, "min_step"),
              fmt::format("min_step ({}) is larger than step ({})", *min_step, *step));
      if (step && end && *step > *end)
        error(t["step"], sub(p, "step"),
              fmt::format("the step ({}) is longer than the run (end {})", *step, *end));
      if (step && end && *end / *step > kMaxSteps)
        error(t["step"], sub(p, "step"),
              fmt::format("end / step = {:.3g} steps, more than the limit of {:.0e}: the step is "
                          "too small for end",
                          *end / *step, kMaxSteps));
      if (auto ad = boolean(t, "adaptive", p)) s.time.adaptive = *ad;
    }
  }
  if (has(a, "newton")) {
    const Node n = a["newton"];
    const std::string p = "analysis.newton";
    if (check_map(n, p,
                  {"tolerance", "max_iterations", "line_search", "reuse_tangent",
                   "reuse_across_steps"})) {
      if (auto tol = positive(n, "tolerance", p, false, "the Newton tolerance"))
        s.newton.tolerance = *tol;
      if (has(n, "max_iterations")) {
        auto it = integer(n["max_iterations"], sub(p, "max_iterations"), "count");
        if (it && *it < 1)
          error(n["max_iterations"], sub(p, "max_iterations"), "at least one iteration is needed");
        else if (it && *it > kMaxNewtonIterations)
          error(n["max_iterations"], sub(p, "max_iterations"),
                fmt::format("at most {} iterations (got {}): Newton that has not converged by "
                            "then has stagnated; give a smaller step instead",
                            kMaxNewtonIterations, *it));
        else if (it)
          s.newton.max_iterations = static_cast<int>(*it);
      }
      if (auto ls = boolean(n, "line_search", p)) s.newton.line_search = *ls;
      if (auto reuse = boolean(n, "reuse_tangent", p)) s.newton.reuse_tangent = *reuse;
      if (auto across = boolean(n, "reuse_across_steps", p)) s.newton.reuse_across_steps = *across;
    }
  }
  if (has(a, "damping")) {
    const Node d = a["damping"];
    const std::string p = "analysis.damping";
    if (check_map(d, p, {"mass", "stiffness"})) {
      in_.model.rayleigh_mass =
          non_negative(d, "mass", p, "the mass-proportional damping").value_or(0);
      in_.model.rayleigh_stiffness =
          non_negative(d, "stiffness", p, "the stiffness-proportional damping").value_or(0);
    }
  }
  if (auto pr = text(a, "predictor", "analysis", false)) {
    if (*pr == "extrapolate")
      s.predictor = AnalysisSettings::Predictor::kExtrapolate;
    else if (*pr == "none")
      s.predictor = AnalysisSettings::Predictor::kNone;
    else
      error(a["predictor"], "analysis.predictor",
            fmt::format("unknown predictor '{}'{}", *pr, suggestion(*pr, {"extrapolate", "none"})));
  }
  if (has(a, "path")) parse_path(a["path"]);
  if (auto ls = text(a, "linear_solver", "analysis", false)) {
    if (*ls == "petsc" && !processes::have_petsc() && !processes::relaunch_with_petsc()) {
      error(a["linear_solver"], "analysis.linear_solver",
            "the PETSc back-end is not available in this build (install petsc-dev and rebuild "
            "with VELUM_WITH_PETSC=ON, or use auto, cholmod, umfpack, klu or mumps)");
    } else {
      try {
        s.solver = solver_kind_from_name(*ls);
        if (s.solver == SolverKind::kMumps && !have_mumps())
          error(a["linear_solver"], "analysis.linear_solver",
                "this build has no MUMPS (install libmumps-seq-dev and rebuild, or use auto, "
                "cholmod, umfpack or klu)");
      } catch (const std::invalid_argument&) {
        error(
            a["linear_solver"], "analysis.linear_solver",
            fmt::format("unknown linear solver '{}'{}", *ls,
                        suggestion(*ls, {"auto", "cholmod", "umfpack", "klu", "mumps", "petsc"})));
      }
    }
  }
  if (auto pa = text(a, "partition", "analysis", false)) {
    if (*pa == "rows")
      s.partition = ElementPartition::kRows;
    else if (*pa == "scotch")
      s.partition = ElementPartition::kScotch;
    else
      error(a["partition"], "analysis.partition",
            fmt::format("unknown partition '{}'{}", *pa, suggestion(*pa, {"rows", "scotch"})));
  }
  if (auto po = text(a, "petsc_options", "analysis", false)) {
    s.petsc_options = *po;
    if (!po->empty() && po->front() != '-')
      error(a["petsc_options"], "analysis.petsc_options",
            fmt::format("PETSc options begin with '-' (as \"-ksp_type gmres -pc_type gamg\"); "
                        "got '{}'",
                        *po));
    else if (s.solver != SolverKind::kPetsc &&
             text(a, "linear_solver", "analysis", false) != "petsc")
      error(a["petsc_options"], "analysis.petsc_options",
            "petsc_options apply to linear_solver: petsc only");
  }
}

// analysis.path: {method: arc_length, constraint, arc_length, max_steps} or
// {method: displacement, node, component, displacement}; static only.
void Reader::parse_path(const Node& pa) {
  const std::string p = "analysis.path";
  if (!check_map(
          pa, p,
          {"method", "constraint", "arc_length", "max_steps", "node", "component", "displacement"}))
    return;
  PathSettings& path = in_.analysis.path;
  if (in_.analysis.type != AnalysisSettings::Type::kStatic)
    error(pa, p, "path following needs type: static");
  auto m = text(pa, "method", p, true);
  if (!m) return;
  auto only_for = [&](const char* key, const char* method) {
    if (has(pa, key))
      error(pa[key], sub(p, key), fmt::format("{} belongs to method: {}", key, method));
  };
  if (*m == "arc_length") {
    path.method = PathSettings::Method::kArcLength;
    if (auto c = text(pa, "constraint", p, false)) {
      if (*c == "cylindrical")
        path.constraint = PathSettings::Constraint::kCylindrical;
      else if (*c == "riks")
        path.constraint = PathSettings::Constraint::kRiks;
      else
        error(
            pa["constraint"], sub(p, "constraint"),
            fmt::format("unknown constraint '{}'{}", *c, suggestion(*c, {"cylindrical", "riks"})));
    }
    if (auto ds = positive(pa, "arc_length", p, false, "the arc length")) path.arc_length = *ds;
    if (has(pa, "max_steps")) {
      auto n = integer(pa["max_steps"], sub(p, "max_steps"), "count");
      if (n && (*n < 1 || *n > 100'000'000))
        error(pa["max_steps"], sub(p, "max_steps"), "max_steps must lie in [1, 1e8]");
      else if (n)
        path.max_steps = static_cast<int>(*n);
    }
    for (const char* k : {"node", "component", "displacement"}) only_for(k, "displacement");
  } else if (*m == "displacement") {
    path.method = PathSettings::Method::kDisplacement;
    auto n = nodes_of(pa, "node", p);
    if (part_ && n && n->empty()) n->push_back(-1);  // another part's node: not here
    if (n && n->size() != 1) {
      error(pa["node"], sub(p, "node"), "give one node");
      n.reset();
    }
    if (!has(pa, "component")) error(pa, sub(p, "component"), "component is required");
    auto c = component(pa, "component", p);
    auto d = number(pa, "displacement", p, true);
    if (n && c && d) path.node = n->front(), path.component = *c, path.displacement = *d;
    for (const char* k : {"constraint", "arc_length", "max_steps"}) only_for(k, "arc_length");
  } else {
    error(pa["method"], sub(p, "method"),
          fmt::format("unknown method '{}'{}", *m, suggestion(*m, {"arc_length", "displacement"})));
  }
}

void Reader::parse_output(const Node& o, const Node& root) {
  OutputSettings& out = in_.output;
  out.directory = base_dir_ / "out";
  out.interval = in_.analysis.time.step;
  const bool given =
      o && check_map(o, "output", {"directory", "interval", "fields", "history", "checkpoint"});
  if (given && has(o, "checkpoint")) {
    const Node c = o["checkpoint"];
    const std::string p = "output.checkpoint";
    if (check_map(c, p, {"steps", "interval"})) {
      if (has(c, "steps") == has(c, "interval"))
        error(c, p,
              "give either steps (every so many accepted steps) or interval (simulated time)");
      if (has(c, "steps")) {
        auto n = integer(c["steps"], sub(p, "steps"), "count");
        if (n && (*n < 1 || *n > 1'000'000'000))
          error(c["steps"], sub(p, "steps"), "steps must lie in [1, 1e9]");
        else if (n)
          out.checkpoint_steps = static_cast<int>(*n);
      }
      if (auto iv = positive(c, "interval", p, false, "the checkpoint interval"))
        out.checkpoint_interval = *iv;
    }
  }
  if (given) {
    if (auto d = text(o, "directory", "output", false)) {
      std::filesystem::path p = *d;
      out.directory = p.is_relative() ? base_dir_ / p : p;
    }
    if (auto iv = positive(o, "interval", "output", false, "the output interval")) {
      out.interval = *iv;
      if (*iv < in_.analysis.time.min_step)
        error(o["interval"], "output.interval", "the output interval is shorter than min_step");
    }
    if (auto f = boolean(o, "fields", "output")) out.fields = *f;
  }
  // Each output time is a history row and, with fields on, a frame (and a rewrite of
  // results.pvd): refuse counts that would fill a disk or take hours of writing alone.
  const double outputs = out.interval > 0 ? in_.analysis.time.t_end / out.interval : 0;
  const double most = out.fields ? kMaxFrames : kMaxOutputTimes;
  if (outputs > most)
    error(given && has(o, "interval") ? o["interval"] : (given ? o : root),
          given && has(o, "interval") ? "output.interval" : "output.interval (default: time.step)",
          fmt::format("end / interval = {:.3g} output times, more than the limit of {:.0e}{}; "
                      "give a longer output.interval",
                      outputs, most, out.fields ? " frames (fields: true)" : " history rows"));
  if (!given) return;
  if (!has(o, "history")) return;
  const Node h = o["history"];
  if (!h.IsSequence()) {
    error(h, "output.history", "expected a list of {name, quantity, ...}");
    return;
  }
  const std::vector<std::string> quantities = {"displacement",
                                               "velocity",
                                               "position",
                                               "reaction",
                                               "fiber_angle_change",
                                               "stress",
                                               "kinetic_energy",
                                               "strain_energy",
                                               "external_work",
                                               "gas_volume",
                                               "gas_pressure",
                                               "gas_temperature",
                                               "gas_mass",
                                               "gas_mass_flow",
                                               "contact_force",
                                               "rigid_position",
                                               "rigid_velocity",
                                               "force",
                                               "slip",
                                               "contact_area",
                                               "rigid_rotation",
                                               "rigid_angular_velocity"};
  std::set<std::string> names;
  for (size_t i = 0; i < h.size(); ++i) {
    const Node e = h[i];
    const std::string p = item("output.history", i);
    if (!check_map(e, p,
                   {"name", "quantity", "node", "nodes", "component", "point", "unit", "load",
                    "inflator", "vent", "leakage", "orifice", "body", "contact", "element"}))
      continue;
    auto name = text(e, "name", p, true);
    auto q = text(e, "quantity", p, true);
    if (!name || !q) continue;
    if (auto why = bad_column_name(*name)) {
      error(e["name"], sub(p, "name"), *why);
      continue;
    }
    if (!names.insert(*name).second) {
      error(e["name"], sub(p, "name"), fmt::format("duplicate history name '{}'", *name));
      continue;
    }
    HistoryEntry he;
    he.name = *name;
    using Q = HistoryEntry::Quantity;
    const auto qi = std::find(quantities.begin(), quantities.end(), *q) - quantities.begin();
    if (qi == static_cast<long>(quantities.size())) {
      error(e["quantity"], sub(p, "quantity"),
            fmt::format("unknown quantity '{}'{}", *q, suggestion(*q, quantities)));
      continue;
    }
    he.quantity = static_cast<Q>(qi);
    bool ok = true;
    switch (he.quantity) {
      case Q::kDisplacement:
      case Q::kVelocity:
      case Q::kPosition: {
        auto n = nodes_of(e, "node", p);
        auto c = component(e, "component", p);
        if (part_ && n && n->empty()) n->push_back(-1);  // another part's node: not here
        if (n && n->size() != 1) {
          error(e["node"], sub(p, "node"), "give one node");
          n.reset();
        }
        ok = n && c;
        if (ok) he.node = n->front(), he.component = *c;
        break;
      }
      case Q::kReaction: {
        auto n = nodes_of(e, "nodes", p);
        auto c = component(e, "component", p);
        ok = n && c;
        if (ok) he.nodes = std::move(*n), he.component = *c;
        break;
      }
      case Q::kFiberAngleChange:
      case Q::kStress: {
        auto pt = vec3(e, "point", p, true);
        ok = pt.has_value();
        if (he.quantity == Q::kStress) {
          auto c = text(e, "component", p, true);
          if (c) {
            const auto ci = std::find_if(kStressComponents.begin(), kStressComponents.end(),
                                         [&](const char* s) { return *c == s; }) -
                            kStressComponents.begin();
            if (ci == static_cast<long>(kStressComponents.size())) {
              error(e["component"], sub(p, "component"),
                    fmt::format(
                        "unknown stress component '{}'{}", *c,
                        suggestion(*c, {kStressComponents.begin(), kStressComponents.end()})));
              ok = false;
            } else {
              he.component = static_cast<int>(ci);
            }
          } else {
            ok = false;
          }
        } else if (auto u = text(e, "unit", p, false)) {
          if (*u == "degree" || *u == "degrees")
            he.degrees = true;
          else if (*u == "radian" || *u == "radians")
            he.degrees = false;
          else {
            error(e["unit"], sub(p, "unit"),
                  fmt::format("unknown unit '{}'{}", *u, suggestion(*u, {"degree", "radian"})));
            ok = false;
          }
        }
        if (ok) {
          he.point = *pt;
          if (!locate(he, out.history.size())) {
            if (mesh_ok_)
              error(e["point"], sub(p, "point"),
                    fmt::format("the point [{}, {}, {}] lies in no membrane element", he.point.x(),
                                he.point.y(), he.point.z()));
            ok = false;
          }
        }
        break;
      }
      case Q::kGasVolume:
      case Q::kGasPressure:
      case Q::kGasTemperature:
      case Q::kGasMass:
      case Q::kGasMassFlow:
        ok = parse_gas_history(e, p, he);
        break;
      case Q::kContactForce:
      case Q::kRigidPosition:
      case Q::kRigidVelocity:
      case Q::kContactArea:
      case Q::kRigidRotation:
      case Q::kRigidAngularVelocity:
        ok = parse_contact_history(e, p, he);
        break;
      case Q::kForce:
        ok = locate_cable(e, p, he, "force", out.history.size());
        break;
      case Q::kSlip:
        ok = parse_slip_history(e, p, he);
        break;
      default:
        break;
    }
    if (ok) out.history.push_back(std::move(he));
  }
}

// `element: id` of a cable element (cable2, cable3 or a sliding_cable chain) for the history
// quantity `force`: its block and position there.
bool Reader::locate_cable(const Node& e, const std::string& p, HistoryEntry& he,
                          const char* quantity, size_t index) {
  if (!require(e, "element", p)) return false;
  auto id = integer(e["element"], sub(p, "element"), "element id");
  if (!id) return false;
  if (part_) {  // a part read: where the split found it (the element may be another part's)
    if (place_from_part(he, index)) return true;
    error(e["element"], sub(p, "element"),
          fmt::format("the split found no cable element {}: split the model again", *id));
    return false;
  }
  for (size_t b = 0; b < in_.element_ids.size() && b < in_.model.blocks.size(); ++b) {
    const auto& ids = in_.element_ids[b];
    const auto at = std::find(ids.begin(), ids.end(), *id);
    if (at == ids.end()) continue;
    if (in_.model.blocks[b]->surface()) {
      error(e["element"], sub(p, "element"),
            std::string_view(quantity) == "force"
                ? fmt::format("element {} is a membrane: the quantity 'force' is a cable's axial "
                              "force (use 'stress' with a point for membranes)",
                              *id)
                : fmt::format("element {} is a membrane: the quantity '{}' is a sliding cable's",
                              *id, quantity));
      return false;
    }
    he.block = static_cast<int>(b);
    he.element = static_cast<int>(at - ids.begin());
    return true;
  }
  if (mesh_ok_)
    error(e["element"], sub(p, "element"), fmt::format("no cable element has the id {}", *id));
  return false;
}

bool Reader::locate(HistoryEntry& he, size_t index) const {
  if (part_) return place_from_part(he, index);
  for (size_t b = 0; b < in_.model.blocks.size(); ++b) {
    const SurfaceBlock* blk = in_.model.blocks[b]->surface();
    if (!blk) continue;
    for (int e = 0; e < blk->size(); ++e)
      if (blk->locate(e, he.point, he.xi)) {
        he.block = static_cast<int>(b);
        he.element = e;
        return true;
      }
  }
  return false;
}

}  // namespace velum::io::model_file
