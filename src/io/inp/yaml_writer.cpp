// A deck as a Velum YAML model (docs/inp-import.md says how each keyword maps). Element sets:
// Velum holds each element in one set, so the elements are partitioned by their section and
// by the pressures they carry; a part keeps the name of its section's *ELSET when it is all of
// it, and is named ELSET_1, ELSET_2, ... otherwise.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <tuple>

#include "model.hpp"

namespace velum::io::inp {
namespace {

/// A name as a YAML scalar: plain when safe, double-quoted otherwise.
std::string yaml_name(const std::string& s) {
  static const std::set<std::string> kSpecial = {"true", "false", "yes", "no", "on",
                                                 "off",  "null",  "y",   "n",  "~"};
  bool plain = !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_');
  for (char c : s)
    plain =
        plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  std::string lower;
  for (char c : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (plain && !kSpecial.count(lower)) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string num(double v) {
  return fmt::format("{}", v);
}
std::string vec(const Vec3& v) {
  return fmt::format("[{}, {}, {}]", num(v.x()), num(v.y()), num(v.z()));
}

std::string id_list(const std::vector<long>& ids, size_t indent) {
  std::string s = "[";
  size_t col = indent + 1;
  for (size_t i = 0; i < ids.size(); ++i) {
    const std::string t = fmt::format("{}{}", ids[i], i + 1 < ids.size() ? ", " : "");
    if (col + t.size() > 98) {
      s += '\n';
      s.append(indent + 1, ' ');
      col = indent + 1;
    }
    s += t;
    col += t.size();
  }
  return s + "]";
}

/// The plane-stress stiffness of an orthotropic sheet in its material axes.
Mat3 orthotropic_q(const Material& m) {
  const double nu21 = m.nu12 * m.E2 / m.E1, d = 1 - m.nu12 * nu21;
  Mat3 Q = Mat3::Zero();
  Q(0, 0) = m.E1 / d, Q(1, 1) = m.E2 / d, Q(0, 1) = Q(1, 0) = m.nu12 * m.E2 / d;
  Q(2, 2) = m.G12;
  return Q;
}

/// Q in sheet axes of a law whose axis 1 is turned by `deg` about the normal from the sheet's
/// m1 towards m2: ε_material = T ε_sheet (engineering shear), Q_sheet = Tᵀ Q T.
Mat3 rotated(const Mat3& Q, double deg) {
  const double a = deg * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
  Mat3 T;
  T << c * c, s * s, c * s, s * s, c * c, -c * s, -2 * c * s, 2 * c * s, c * c - s * s;
  const Mat3 R = T.transpose() * Q * T;
  return 0.5 * (R + R.transpose());  // symmetric to the last digit
}

}  // namespace

std::string write_yaml(const std::string& title, const Mesh& mesh, const Properties& props,
                       const std::vector<Step>& deck_steps, Diagnostics& diag) {
  auto at = [&](int file, int line) { return diag.where(file, line); };
  if (deck_steps.empty()) return {};
  // Several steps: each complete (what it holds from the steps before), as Velum's steps:.
  const std::vector<Step> steps =
      deck_steps.size() > 1 ? complete_steps(deck_steps, diag) : deck_steps;
  const bool staged = steps.size() > 1;
  const Step& step = steps.front();  // the model data (initial stress, output requests)
  const std::map<std::string, Amplitude>& amplitudes = steps.back().amplitudes;  // all of them
  // ---- sections: which elements each one holds ----
  std::vector<int> section_of(mesh.elements.size(), -1);
  for (size_t s = 0; s < props.sections.size(); ++s) {
    const Section& sec = props.sections[s];
    const std::string here = at(sec.file, sec.line);
    const Set* es = mesh.elset(sec.elset);
    if (!es) {
      diag.errors.push_back(
          fmt::format("{}: section: undefined element set '{}'", here, sec.elset));
      continue;
    }
    for (long id : es->ids) {
      const size_t e = mesh.element_at.at(id);
      const bool cable = mesh.elements[e].type.rfind("cable", 0) == 0;
      if (sec.membrane == cable) {
        diag.errors.push_back(fmt::format(
            "{}: section: element {} of set '{}' is a {}: give it a *{}", here, id, es->name,
            cable ? "truss" : "membrane", cable ? "SOLID SECTION" : "MEMBRANE SECTION"));
        break;
      }
      if (section_of[e] >= 0) {
        const Section& other = props.sections[static_cast<size_t>(section_of[e])];
        diag.errors.push_back(fmt::format("{}: section: element {} has a section already ({})",
                                          here, id, at(other.file, other.line)));
        break;
      }
      section_of[e] = static_cast<int>(s);
    }
  }
  for (size_t e = 0; e < mesh.elements.size(); ++e)
    if (section_of[e] < 0) {
      const Element& el = mesh.elements[e];
      diag.errors.push_back(
          fmt::format("{}: *ELEMENT: element {} has no section (*MEMBRANE "
                      "SECTION or *SOLID SECTION)",
                      at(el.file, el.line), el.id));
      break;
    }
  if (!step.present)
    diag.errors.push_back(fmt::format("{}: the deck has no *STEP: nothing to solve",
                                      diag.files.empty() ? "" : diag.files[0]));
  if (!diag.errors.empty()) return {};

  // ---- parts: elements with the same section and the same pressures ----
  // (step, pressure) pairs per element
  std::vector<std::vector<std::pair<int, int>>> pressures_of(mesh.elements.size());
  for (size_t k = 0; k < steps.size(); ++k)
    for (size_t p = 0; p < steps[k].pressures.size(); ++p)
      for (long id : steps[k].pressures[p].elements)
        pressures_of[mesh.element_at.at(id)].emplace_back(static_cast<int>(k), static_cast<int>(p));
  // ... and the same prestress (*INITIAL CONDITIONS, TYPE=STRESS).
  struct Part {
    std::string name;
    int section = 0;
    std::vector<size_t> elements;
    std::array<double, 3> prestress{};
  };
  std::vector<Part> parts;
  std::map<std::tuple<int, std::vector<std::pair<int, int>>, std::array<double, 3>>, size_t>
      part_at;
  for (size_t e = 0; e < mesh.elements.size(); ++e) {
    std::array<double, 3> S{};
    if (auto it = step.initial_stress.find(mesh.elements[e].id); it != step.initial_stress.end())
      S = {it->second[0], it->second[1], it->second[2]};
    auto [it, fresh] = part_at.try_emplace({section_of[e], pressures_of[e], S}, parts.size());
    if (fresh) parts.push_back({"", section_of[e], {}, S});
    parts[it->second].elements.push_back(e);
  }
  std::map<int, int> count;
  for (const auto& p : parts) ++count[p.section];
  std::map<int, int> numbered;
  for (auto& p : parts) {
    const std::string base = mesh.elset(props.sections[static_cast<size_t>(p.section)].elset)->name;
    p.name = count[p.section] == 1 ? base : fmt::format("{}_{}", base, ++numbered[p.section]);
  }

  // ---- materials: one Velum material per (material, use) ----
  std::string materials_yaml;
  std::map<std::string, std::string> velum_material;  // (material + use) -> name
  std::set<std::string> material_names;
  auto material_for = [&](const Section& sec, const Orientation* o) -> std::optional<std::string> {
    const std::string here = at(sec.file, sec.line);
    auto mit = props.material_at.find(sec.material);
    if (mit == props.material_at.end()) {
      diag.errors.push_back(
          fmt::format("{}: section: undefined material '{}'", here, sec.material));
      return std::nullopt;
    }
    const Material& m = props.materials[mit->second];
    const double angle = o ? o->angle : 0;
    const std::string use = !sec.membrane ? "truss" : angle != 0 ? fmt::format("{}", angle) : "";
    const std::string key = sec.material + "|" + use;
    if (auto it = velum_material.find(key); it != velum_material.end()) return it->second;
    const std::string mhere = at(m.file, m.line);
    if (m.law == Material::Law::kNone) {
      diag.errors.push_back(fmt::format("{}: *MATERIAL: '{}' has no *ELASTIC", mhere, m.name));
      return std::nullopt;
    }
    if (!m.density &&
        std::any_of(steps.begin(), steps.end(), [](const Step& st) { return st.dynamic; })) {
      diag.errors.push_back(
          fmt::format("{}: *MATERIAL: '{}' has no *DENSITY, which a dynamic "
                      "step needs",
                      mhere, m.name));
      return std::nullopt;
    }
    std::string name = m.name;
    if (!sec.membrane) name += "_truss";
    if (angle != 0) name += fmt::format("_{}deg", angle);
    while (material_names.count(name)) name += "_";
    std::string law;
    if (!sec.membrane) {
      if (m.law != Material::Law::kIsotropic) {
        diag.errors.push_back(
            fmt::format("{}: section: a truss needs an isotropic *ELASTIC ('{}' "
                        "is {})",
                        here, m.name, m.elastic_type));
        return std::nullopt;
      }
      law = fmt::format("type: cable, E: {}, compression: {}", num(m.E),
                        m.no_compression ? "false" : "true");
    } else {
      if (m.no_compression) {
        diag.errors.push_back(
            fmt::format("{}: *MATERIAL: '{}': *NO COMPRESSION maps to cables "
                        "only (for sheets, a YAML section's wrinkling: true is "
                        "the tension-field law)",
                        mhere, m.name));
        return std::nullopt;
      }
      Mat3 Q;
      if (m.law == Material::Law::kIsotropic) {
        law = fmt::format("type: isotropic, E: {}, nu: {}", num(m.E), num(m.nu));
      } else if (m.law == Material::Law::kOrthotropic && angle == 0) {
        law = fmt::format("type: orthotropic, E1: {}, E2: {}, nu12: {}, G12: {}", num(m.E1),
                          num(m.E2), num(m.nu12), num(m.G12));
      } else {
        Q = m.law == Material::Law::kOrthotropic ? orthotropic_q(m) : m.Q;
        Q = rotated(Q, angle);
        law = fmt::format("type: matrix, Q: [[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]",
                          num(Q(0, 0)), num(Q(0, 1)), num(Q(0, 2)), num(Q(1, 0)), num(Q(1, 1)),
                          num(Q(1, 2)), num(Q(2, 0)), num(Q(2, 1)), num(Q(2, 2)));
      }
    }
    material_names.insert(name);
    velum_material[key] = name;
    materials_yaml += fmt::format("  {}: {{{}, density: {}}}   # {}\n", yaml_name(name), law,
                                  num(m.density.value_or(0)), mhere);
    return name;
  };

  std::string sections_yaml;
  for (const auto& p : parts) {
    const Section& sec = props.sections[static_cast<size_t>(p.section)];
    const Orientation* o = nullptr;
    if (!sec.orientation.empty()) {
      auto it = props.orientation_at.find(sec.orientation);
      if (it == props.orientation_at.end()) {
        diag.errors.push_back(fmt::format("{}: section: undefined orientation '{}'",
                                          at(sec.file, sec.line), sec.orientation));
        continue;
      }
      o = &props.orientations[it->second];
    }
    auto mat = material_for(sec, o);
    if (!mat) continue;
    std::string axes;
    if (o) {
      auto point = [&](long node, const Vec3& x) {
        if (!o->by_nodes) return vec(x);
        if (node == 0) return vec(Vec3::Zero());
        if (!mesh.node_at.count(node))
          diag.errors.push_back(
              fmt::format("{}: *ORIENTATION: undefined node {}", at(o->file, o->line), node));
        return std::to_string(node);
      };
      axes = fmt::format(", axes: {{points: [{}, {}, {}]}}", point(o->nc, o->c), point(o->na, o->a),
                         point(o->nb, o->b));
    } else if (sec.membrane && (props.materials[props.material_at.at(sec.material)].law !=
                                    Material::Law::kIsotropic ||
                                p.prestress[0] != p.prestress[1] || p.prestress[2] != 0)) {
      axes = ", axes: {points: [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}";  // Abaqus: global x projected
      // Where global x is within 0.1° of a sheet's normal, Abaqus projects global z instead
      // and Velum global y: refused rather than mapped differently.
      for (size_t e : p.elements) {
        const Element& el = mesh.elements[e];
        auto X = [&](size_t k) { return mesh.nodes[mesh.node_at.at(el.nodes[k])].x; };
        const bool tri = el.type.rfind("tri", 0) == 0;
        const Vec3 n =
            tri ? Vec3((X(1) - X(0)).cross(X(2) - X(0))) : Vec3((X(2) - X(0)).cross(X(3) - X(1)));
        if (n.norm() > 0 && std::abs(n.normalized().x()) > std::cos(0.1 * std::numbers::pi / 180)) {
          diag.errors.push_back(fmt::format(
              "{}: section: element {} lies normal to global x, where Abaqus's default material "
              "axes (global z projected) differ from Velum's (global y projected): give the "
              "section an *ORIENTATION",
              at(sec.file, sec.line), el.id));
          break;
        }
      }
    }
    std::string prestress;  // in the material axes; a truss's as its force S11 A
    if (p.prestress != std::array<double, 3>{})
      prestress = sec.membrane ? fmt::format(", prestress: [{}, {}, {}]", num(p.prestress[0]),
                                             num(p.prestress[1]), num(p.prestress[2]))
                               : fmt::format(", prestress: {}", num(p.prestress[0] * sec.size));
    sections_yaml +=
        fmt::format("  - {{elements: {}, material: {}, {}: {}{}{}}}   # {}\n", yaml_name(p.name),
                    yaml_name(*mat), sec.membrane ? "thickness" : "area", num(sec.size), axes,
                    prestress, at(sec.file, sec.line));
  }

  // ---- functions ----
  std::set<std::string> used_amplitudes;
  std::map<std::string, double> ramps;                 // the steps' default ramps: name -> duration
  std::map<std::string, std::string> extra_functions;  // name -> its YAML
  bool riks_amplitude_warned = false, riks_used = false;
  std::vector<double> starts(steps.size(), 0.0);  // each step's start in total time
  for (size_t k = 1; k < steps.size(); ++k) starts[k] = starts[k - 1] + steps[k - 1].period;
  auto function = [&](const Step& st, size_t k, const std::string& amp) -> std::string {
    if (amp == "=held") return "";  // held at its value at the end of the step before
    if (st.riks) {                  // every load scales with the load proportionality factor
      if (!amp.empty() && !riks_amplitude_warned) {
        riks_amplitude_warned = true;
        diag.warnings.push_back(fmt::format(
            "{}: *STATIC, RIKS: the loads' amplitudes are not used (as in Abaqus): every load "
            "scales with the load proportionality factor",
            at(st.file, st.line)));
      }
      riks_used = true;
      return ", function: riks_lpf";
    }
    if (!amp.empty()) {
      const Amplitude& a = amplitudes.at(amp);
      if (a.total_time && starts[k] > 0) {  // Velum's step functions run in step time
        const std::string name = fmt::format("{}_step{}", a.name, k + 1);
        std::string pts;
        for (const auto& [t, v] : a.points)
          pts += fmt::format("{}[{}, {}]", pts.empty() ? "" : ", ", num(t - starts[k]), num(v));
        extra_functions[name] = fmt::format("{{type: table, points: [{}]}}", pts);
        return ", function: " + yaml_name(name);
      }
      used_amplitudes.insert(amp);
      return ", function: " + yaml_name(a.name);
    }
    if (!st.ramp_default) return "";
    const std::string name = staged ? fmt::format("step_ramp_{}", k + 1) : "step_ramp";
    ramps[name] = st.period;
    return ", function: " + name;
  };

  // ---- boundary and loads of step k, each line starting with `indent` ----
  auto boundary_and_loads = [&](const Step& st, size_t k, const std::string& indent) {
    // per node, its fixed components and its prescribed motion
    struct NodeMotion {
      std::array<bool, 3> fixed{false, false, false}, moved{false, false, false};
      Vec3 d = Vec3::Zero(), from = Vec3::Zero();
      std::set<std::string> amplitudes;
      std::string where;
    };
    std::map<long, NodeMotion> motion;
    for (const auto& [key, c] : st.constraints) {
      NodeMotion& m = motion[key.first];
      const auto comp = static_cast<size_t>(key.second);
      if (!c.prescribed || c.value == 0) {
        m.fixed[comp] = true;
        continue;
      }
      m.moved[comp] = true;
      m.d[key.second] = c.value;
      m.where = c.where;
      if (c.amplitude == "=held") {
        m.from[key.second] = c.value;
        m.amplitudes.insert("=held");
      } else if (c.amplitude.rfind("=from:", 0) == 0) {
        m.from[key.second] = std::stod(c.amplitude.substr(6));
        m.amplitudes.insert("=ramp");
      } else {
        m.amplitudes.insert(c.amplitude.empty() && st.ramp_default ? "=ramp" : c.amplitude);
      }
    }
    std::map<std::array<bool, 3>, std::vector<long>> fixes;
    std::map<std::pair<std::array<double, 3>, std::string>, std::vector<long>> moves;
    for (const auto& [node, m] : motion) {
      const bool moving = std::any_of(m.moved.begin(), m.moved.end(), [](bool b) { return b; });
      if (moving) {
        for (size_t c = 0; c < 3; ++c)
          if (!m.moved[c] && !m.fixed[c]) {
            diag.errors.push_back(fmt::format(
                "{}: *BOUNDARY: node {} is given a displacement with its component {} free: "
                "Velum prescribes all three components of a moving node (fix or prescribe it)",
                m.where, node, c + 1));
            break;
          }
        // One time function per node: held, a ramp from where it is (its components in a
        // fixed ratio), or one amplitude.
        std::string amp;
        if (m.amplitudes.size() == 1 && *m.amplitudes.begin() != "=ramp") {
          amp = *m.amplitudes.begin();
        } else if (m.amplitudes.count("=ramp") &&
                   (m.amplitudes.size() == 1 ||
                    (m.amplitudes.size() == 2 && m.amplitudes.count("=held")))) {
          const double r = m.from.dot(m.d) / m.d.squaredNorm();
          if ((m.from - r * m.d).norm() > 1e-12 * m.d.norm()) {
            diag.errors.push_back(fmt::format(
                "{}: *BOUNDARY: node {} moves on from [{}, {}, {}] to [{}, {}, {}]: Velum "
                "prescribes a node's motion as one vector times one time function, so a motion "
                "that changes direction between steps cannot be written",
                m.where, node, m.from.x(), m.from.y(), m.from.z(), m.d.x(), m.d.y(), m.d.z()));
            continue;
          }
          if (r == 0) {
            amp = "";
          } else {
            const std::string name = fmt::format("on_from_{}_step{}", num(r), k + 1);
            extra_functions[name] =
                fmt::format("{{type: table, points: [[0, {}], [{}, 1]]}}", num(r), num(st.period));
            amp = "=fn:" + name;
          }
        } else {
          diag.errors.push_back(fmt::format(
              "{}: *BOUNDARY: node {} moves with two amplitudes: Velum gives a node one time "
              "function",
              m.where, node));
          continue;
        }
        moves[{{m.d.x(), m.d.y(), m.d.z()}, amp}].push_back(node);
      }
      if (std::any_of(m.fixed.begin(), m.fixed.end(), [](bool b) { return b; }))
        fixes[m.fixed].push_back(node);
    }
    std::string boundary_yaml;
    const size_t col = indent.size() + 9;
    for (const auto& [fix, nodes] : fixes) {
      std::string comps;
      for (size_t c = 0; c < 3; ++c)
        if (fix[c]) {
          if (!comps.empty()) comps += ", ";
          comps += "xyz"[c];
        }
      boundary_yaml +=
          fmt::format("{}- {{nodes: {}, fix: [{}]}}\n", indent, id_list(nodes, col), comps);
    }
    for (const auto& [key, nodes] : moves)
      boundary_yaml +=
          fmt::format("{}- {{nodes: {}, displacement: {}{}}}\n", indent, id_list(nodes, col),
                      vec(Vec3(key.first[0], key.first[1], key.first[2])),
                      key.second.rfind("=fn:", 0) == 0 ? ", function: " + key.second.substr(4)
                                                       : function(st, k, key.second));

    // loads
    std::map<std::pair<long, std::string>, Vec3> node_force;
    auto add_force = [&](const std::pair<long, int>& key, const NodeLoad& l) {
      auto [it, fresh] = node_force.try_emplace({key.first, l.amplitude}, Vec3::Zero());
      it->second[key.second] += l.value;
    };
    for (const auto& [key, l] : st.loads) add_force(key, l);
    for (const auto& [key, l] : st.held_loads) add_force(key, l);
    std::map<std::pair<std::array<double, 3>, std::string>, std::vector<long>> forces;
    for (const auto& [key, f] : node_force)
      forces[{{f.x(), f.y(), f.z()}, key.second}].push_back(key.first);
    std::string loads_yaml;
    for (const auto& [key, nodes] : forces)
      loads_yaml += fmt::format(
          "{}- {{type: point, nodes: {}, force: {}{}}}\n", indent, id_list(nodes, col),
          vec(Vec3(key.first[0], key.first[1], key.first[2])), function(st, k, key.second));
    for (size_t p = 0; p < st.pressures.size(); ++p) {
      const Pressure& pr = st.pressures[p];
      const std::pair<int, int> id{static_cast<int>(k), static_cast<int>(p)};
      for (const auto& part : parts) {
        const auto& of = pressures_of[part.elements[0]];
        if (std::find(of.begin(), of.end(), id) != of.end())
          loads_yaml += fmt::format("{}- {{type: pressure, elements: {}, value: {}{}}}   # {}\n",
                                    indent, yaml_name(part.name), num(pr.value),
                                    function(st, k, pr.amplitude), pr.where);
      }
    }
    for (const auto& g : st.gravity)
      loads_yaml += fmt::format("{}- {{type: gravity, acceleration: {}{}}}   # {}\n", indent,
                                vec(g.acceleration), function(st, k, g.amplitude), g.where);
    return std::pair{boundary_yaml, loads_yaml};
  };

  // ---- the analysis of step k ----
  auto analysis = [&](const Step& st, const std::string& indent) {
    std::string a = fmt::format("{}type: {}\n", indent, st.dynamic ? "dynamic" : "static");
    if (st.dynamic)
      a += fmt::format("{}integrator: {{scheme: hht, alpha: {}}}\n", indent, num(-st.alpha));
    if (st.riks) {
      a += fmt::format("{}time: {{end: {}, step: {}, min_step: {}}}   # {}\n", indent,
                       num(st.max_lpf), num(st.initial), num(st.min_inc), at(st.file, st.line));
      a += fmt::format("{}path: {{method: arc_length{}}}\n", indent,
                       st.max_steps > 0 ? fmt::format(", max_steps: {}", st.max_steps) : "");
    } else {
      a += fmt::format("{}time: {{end: {}, step: {}, min_step: {}, adaptive: {}}}   # {}\n", indent,
                       num(st.period), num(st.initial), num(st.min_inc),
                       st.direct ? "false" : "true", at(st.file, st.line));
    }
    return a;
  };

  std::string boundary_yaml, loads_yaml, steps_yaml;
  if (!staged) {
    std::tie(boundary_yaml, loads_yaml) = boundary_and_loads(step, 0, "  ");
  } else {
    std::set<std::string> names;
    for (size_t k = 0; k < steps.size(); ++k) {
      const Step& st = steps[k];
      std::string name = st.name.empty() ? fmt::format("Step-{}", k + 1) : st.name;
      while (!names.insert(canonical(name)).second) name += "_";
      auto [b, l] = boundary_and_loads(st, k, "      ");
      steps_yaml += fmt::format("  - name: {}   # {}\n    analysis:\n{}", yaml_name(name),
                                at(st.file, st.line), analysis(st, "      "));
      steps_yaml += b.empty() ? "    boundary: []\n" : "    boundary:\n" + b;
      steps_yaml += l.empty() ? "    loads: []\n" : "    loads:\n" + l;
    }
  }

  if (!diag.errors.empty()) return {};

  // ---- the file ----
  std::string y = "# Written by velum import from " + diag.files[0] +
                  " (docs/inp-import.md); comments name the deck's lines.\n";
  if (!title.empty()) y += "title: " + yaml_name(title) + "\n";
  y += "mesh:\n  nodes:\n";
  for (const auto& n : mesh.nodes)
    y += fmt::format("    - [{}, {}, {}, {}]\n", n.id, num(n.x.x()), num(n.x.y()), num(n.x.z()));
  y += "  elements:\n";
  for (const auto& p : parts) {
    std::map<std::string, std::vector<size_t>> by_type;
    for (size_t e : p.elements) by_type[mesh.elements[e].type].push_back(e);
    for (const auto& [type, els] : by_type) {
      std::vector<long> ids;
      for (size_t e : els) ids.push_back(mesh.elements[e].id);
      y += fmt::format("    - set: {}\n      type: {}\n      ids: {}\n      connectivity:\n",
                       yaml_name(p.name), type, id_list(ids, 11));
      for (size_t e : els)
        y += fmt::format("        - [{}]\n", fmt::join(mesh.elements[e].nodes, ", "));
    }
  }
  if (!mesh.nsets.empty()) {
    y += "  node_sets:\n";
    for (const auto& s : mesh.nsets)
      if (!s.ids.empty())
        y += fmt::format("    {}: {}\n", yaml_name(s.name), id_list(s.ids, 8 + s.name.size()));
  }
  y += "materials:\n" + materials_yaml + "sections:\n" + sections_yaml;
  if (!boundary_yaml.empty()) y += "boundary:\n" + boundary_yaml;
  if (!loads_yaml.empty()) y += "loads:\n" + loads_yaml;
  if (riks_used || !ramps.empty() || !used_amplitudes.empty() || !extra_functions.empty()) {
    y += "functions:\n";
    if (riks_used)  // linear over every factor the path may visit
      y += fmt::format(
          "  riks_lpf: {{type: table, points: [[-{0}, -{0}], [{0}, {0}]]}}   # the load "
          "proportionality factor\n",
          num(std::pow(10.0, std::ceil(std::log10(step.max_lpf)) + 3)));
    for (const auto& [name, duration] : ramps)
      y += fmt::format("  {}: {{type: ramp, duration: {}}}   # the step's default\n", name,
                       num(duration));
    for (const auto& a : used_amplitudes) {
      const Amplitude& amp = amplitudes.at(a);
      std::string pts;
      for (const auto& [t, v] : amp.points)
        pts += fmt::format("{}[{}, {}]", pts.empty() ? "" : ", ", num(t), num(v));
      y += fmt::format("  {}: {{type: table, points: [{}]}}\n", yaml_name(amp.name), pts);
    }
    for (const auto& [name, text] : extra_functions)
      y += fmt::format("  {}: {}\n", yaml_name(name), text);
  }
  if (staged) {
    y += "steps:\n" + steps_yaml;
  } else {
    y += "analysis:\n" + analysis(step, "  ");
  }
  double interval = std::numeric_limits<double>::infinity();
  for (const Step& st : steps)
    interval = std::min(interval, st.riks ? st.initial : std::max(st.initial, st.period / 100));
  y += fmt::format("output:\n  interval: {}\n  fields: true\n", num(interval));
  if (!step.history.empty()) {
    y += "  history:\n";
    for (const auto& h : step.history) {
      std::string what;
      if (h.quantity == "reaction")
        what = h.set.empty() ? fmt::format("nodes: [{}]", h.set_node)
                             : fmt::format("nodes: {}", yaml_name(h.set));
      else if (h.node)
        what = fmt::format("node: {}", h.node);
      if (h.component >= 0) what += fmt::format(", component: {}", "xyz"[h.component]);
      y += fmt::format("    - {{name: {}, quantity: {}{}{}}}   # {}\n", yaml_name(h.name),
                       h.quantity, what.empty() ? "" : ", ", what, h.where);
    }
  }
  return y;
}

}  // namespace velum::io::inp
