// Reads functions:, masses:, boundary: and loads:.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>

#include "reader.hpp"

namespace velum::io::model_file {

void Reader::parse_functions(const Node& fs) {
  if (!fs) return;
  if (!fs.IsMap()) {
    error(fs, "functions", "expected a mapping of name: {type: ...}");
    return;
  }
  for (const auto& kv : fs) {
    const std::string fname = kv.first.Scalar();
    const std::string path = sub("functions", fname);
    const Node f = kv.second;
    if (!check_map(f, path, {"type", "duration", "points"})) continue;
    auto type = text(f, "type", path, true);
    if (!type) continue;
    TimeFunction tf;
    tf.name = fname;
    if (*type == "step") {
      tf.kind = TimeFunction::Kind::kConstant;
      tf.value = 1;
    } else if (*type == "ramp") {
      tf.kind = TimeFunction::Kind::kRamp;
      auto d = positive(f, "duration", path, true, "the ramp duration");
      if (!d) continue;
      tf.duration = *d;
    } else if (*type == "table") {
      tf.kind = TimeFunction::Kind::kTable;
      if (!require(f, "points", path)) continue;
      const Node pts = f["points"];
      const std::string pp = sub(path, "points");
      if (!pts.IsSequence() || pts.size() == 0) {
        error(pts, pp, "expected a list of [time, value] pairs");
        continue;
      }
      bool ok = true;
      for (size_t i = 0; i < pts.size() && ok; ++i) {
        if (!pts[i].IsSequence() || pts[i].size() != 2) {
          error(pts[i], item(pp, i), "expected a pair [time, value]");
          ok = false;
          break;
        }
        auto t = number(pts[i][0], item(pp, i));
        auto v = number(pts[i][1], item(pp, i));
        if (!t || !v) {
          ok = false;
          break;
        }
        if (!tf.points.empty() && *t <= tf.points.back().first) {
          error(pts[i], item(pp, i), "table times must increase strictly");
          ok = false;
        }
        tf.points.emplace_back(*t, *v);
      }
      if (!ok) continue;
    } else {
      error(f["type"], sub(path, "type"),
            fmt::format("unknown function type '{}'{}", *type,
                        suggestion(*type, {"step", "ramp", "table"})));
      continue;
    }
    functions_[fname] = static_cast<int>(in_.model.functions.size());
    in_.model.functions.push_back(std::move(tf));
  }
}

/// Index of a function named in map[key]; -1 (constant 1) when absent or "step".
int Reader::function_ref(const Node& map, const std::string& path) {
  auto f = text(map, "function", path, false);
  if (!f) return -1;
  if (auto it = functions_.find(*f); it != functions_.end()) return it->second;
  if (*f == "step") return -1;
  auto names = keys_of(functions_);
  names.push_back("step");
  error(map["function"], sub(path, "function"),
        fmt::format("undefined function '{}'{}", *f, suggestion(*f, names)));
  return -1;
}

void Reader::parse_masses(const Node& ms) {
  if (!ms.IsSequence()) {
    error(ms, "masses", "expected a list of {node, mass, drag}");
    return;
  }
  for (size_t i = 0; i < ms.size(); ++i) {
    const Node m = ms[i];
    const std::string p = item("masses", i);
    if (!check_map(m, p, {"node", "mass", "drag"})) continue;
    auto nodes = nodes_of(m, "node", p);
    auto mass = positive(m, "mass", p, true, "the mass");
    double rho = 0, cda = 0;
    if (has(m, "drag")) {
      const Node d = m["drag"];
      const std::string dp = sub(p, "drag");
      if (check_map(d, dp, {"rho", "cd_area"})) {
        rho = non_negative(d, "rho", dp, "the air density").value_or(0);
        cda = non_negative(d, "cd_area", dp, "cd_area").value_or(0);
        require(d, "rho", dp);
        require(d, "cd_area", dp);
      }
    }
    if (!nodes || !mass) continue;
    for (int n : *nodes) {
      in_.model.masses.push_back({n, *mass});
      if (rho != 0 || cda != 0) in_.model.drag.push_back({n, rho, cda});
    }
  }
}

void Reader::parse_boundary(const Node& bs) {
  if (!bs.IsSequence()) {
    error(bs, "boundary", "expected a list of {nodes, fix | displacement | symmetry}");
    return;
  }
  // Which entries fix, prescribe or put on a plane each node. A fixed component is a
  // prescribed zero: a displacement that is not zero there, a second displacement that
  // differs, or one with a component along a symmetry plane's normal asks two motions of one
  // node; a fixed component on a skew plane's node would fix a component of its local frame
  // instead. Each is an error naming both entries.
  struct Claims {
    int fixed = -1, prescribed = -1, plane = -1, skew = -1;  // entry index, -1: none
    std::array<bool, 3> fix{false, false, false};
    Vec3 normal = Vec3::Zero();
  };
  struct Motion {
    Vec3 d = Vec3::Zero();
    int function = -1;
  };
  std::vector<Claims> claims(static_cast<size_t>(in_.model.num_nodes()));
  std::vector<Motion> motions(bs.size());
  auto entry = [&](int k) {
    return fmt::format("boundary[{}], line {}", k,
                       std::max(line_of(bs[static_cast<size_t>(k)]), 1));
  };
  auto conflict = [&](const Node& at, const std::string& p, int n, const char* here, int other,
                      const char* there) {
    error(at, sub(p, "nodes"),
          fmt::format("node {} is {} here and {} by {}: give each node one motion",
                      in_.model.node_ids[static_cast<size_t>(n)], here, there, entry(other)));
  };
  auto moves_fixed = [](const Claims& c, const Vec3& d) {
    return (c.fix[0] && d[0] != 0) || (c.fix[1] && d[1] != 0) || (c.fix[2] && d[2] != 0);
  };
  for (size_t i = 0; i < bs.size(); ++i) {
    const Node b = bs[i];
    const std::string p = item("boundary", i);
    const int me = static_cast<int>(i);
    if (!check_map(b, p, {"nodes", "fix", "displacement", "function", "symmetry"})) continue;
    auto nodes = nodes_of(b, "nodes", p);
    const int kinds = has(b, "fix") + has(b, "displacement") + has(b, "symmetry");
    if (kinds != 1) {
      error(b, p, "give exactly one of fix, displacement or symmetry");
      continue;
    }
    if (has(b, "fix")) {
      FixedDofs f;
      const Node fx = b["fix"];
      const std::string fp = sub(p, "fix");
      bool ok = fx.IsSequence() && fx.size() > 0;
      if (!ok) error(fx, fp, "expected a list of components, e.g. [x, y, z]");
      for (size_t k = 0; ok && k < fx.size(); ++k) {
        const std::string c = fx[k].IsScalar() ? fx[k].Scalar() : "";
        if (c == "x" || c == "y" || c == "z") {
          f.fix[static_cast<size_t>(c[0] - 'x')] = true;
        } else {
          error(fx[k], fp,
                fmt::format("unknown component '{}'{}", c, suggestion(c, {"x", "y", "z"})));
          ok = false;
        }
      }
      if (has(b, "function"))
        error(b["function"], sub(p, "function"), "a fixed boundary takes no function");
      if (ok && nodes) {
        for (int n : *nodes) {
          auto& c = claims[static_cast<size_t>(n)];
          for (size_t k = 0; k < 3; ++k) c.fix[k] = c.fix[k] || f.fix[k];
          if (c.prescribed >= 0 && moves_fixed(c, motions[static_cast<size_t>(c.prescribed)].d)) {
            conflict(b, p, n, "fixed", c.prescribed, "given a non-zero displacement there");
            break;
          }
          if (c.skew >= 0) {
            conflict(b, p, n, "fixed", c.skew, "put on a skew symmetry plane");
            break;
          }
          if (c.fixed < 0) c.fixed = me;
        }
        f.nodes = std::move(*nodes);
        in_.model.fixed.push_back(std::move(f));
      }
    } else if (has(b, "displacement")) {
      auto d = vec3(b, "displacement", p, true);
      const int fn = function_ref(b, p);
      if (d && nodes) {
        motions[i] = {*d, fn};
        for (int n : *nodes) {
          auto& c = claims[static_cast<size_t>(n)];
          if (c.fixed >= 0 && moves_fixed(c, *d)) {
            conflict(b, p, n, "given a non-zero displacement of a component", c.fixed, "fixed");
            break;
          }
          if (c.prescribed >= 0) {
            const Motion& other = motions[static_cast<size_t>(c.prescribed)];
            if (other.d != *d || other.function != fn) {
              conflict(b, p, n, "given a displacement", c.prescribed, "given a different one");
              break;
            }
          }
          if (c.plane >= 0 && c.normal.dot(*d) != 0) {
            conflict(b, p, n, "given a displacement off the plane", c.plane,
                     "put on a symmetry plane");
            break;
          }
          if (c.prescribed < 0) c.prescribed = me;
        }
        in_.model.prescribed.push_back({std::move(*nodes), *d, fn});
      }
    } else {
      const Node s = b["symmetry"];
      const std::string sp = sub(p, "symmetry");
      if (!check_map(s, sp, {"normal"})) continue;
      auto n = vec3(s, "normal", sp, true);
      if (n && n->norm() == 0) {
        error(s["normal"], sub(sp, "normal"), "the plane normal must not be zero");
        n.reset();
      }
      if (n && nodes) {
        const Vec3 unit = n->normalized();
        const bool skew = (unit.cwiseAbs().array() - 1.0).abs().minCoeff() >= 1e-12;
        for (int k : *nodes) {
          auto& c = claims[static_cast<size_t>(k)];
          if (c.prescribed >= 0 && unit.dot(motions[static_cast<size_t>(c.prescribed)].d) != 0) {
            conflict(b, p, k, "put on a symmetry plane", c.prescribed,
                     "given a displacement off it");
            break;
          }
          if (skew && c.fixed >= 0) {
            conflict(b, p, k, "put on a skew symmetry plane", c.fixed, "fixed");
            break;
          }
          if (c.plane < 0) c.plane = me, c.normal = unit;
          if (skew && c.skew < 0) c.skew = me;
        }
        in_.model.symmetry.push_back({std::move(*nodes), unit});
      }
    }
  }
}

const std::vector<std::pair<std::string, Reader::LoadParser>>& Reader::load_parsers() {
  // A new load: its class (src/load/), its parser here, its test.
  static const std::vector<std::pair<std::string, LoadParser>> table = {
      {"point", &Reader::parse_point_load},       {"edge", &Reader::parse_edge_load},
      {"pressure", &Reader::parse_pressure_load}, {"gas", &Reader::parse_gas_load},
      {"gravity", &Reader::parse_gravity_load},
  };
  return table;
}

void Reader::add_load(std::unique_ptr<Load> load, const Node& at, const std::string& path) {
  load_sites_.push_back({&in_.model.loads.add(std::move(load)), at, path});
}

void Reader::set_up_loads() {
  const ElementNamer name = [&](int block, int element) {
    const auto& ids = in_.element_ids[static_cast<size_t>(block)];
    return static_cast<size_t>(element) < ids.size() ? ids[static_cast<size_t>(element)]
                                                     : static_cast<long>(element) + 1;
  };
  for (auto& load : in_.model.loads) {
    const auto site = std::find_if(load_sites_.begin(), load_sites_.end(),
                                   [&](const LoadAt& s) { return s.load == load.get(); });
    try {
      load->set_up(in_.model, name);
    } catch (const std::invalid_argument& e) {
      if (site != load_sites_.end()) error(site->at, site->path, e.what());
    }
  }
}

void Reader::parse_loads(const Node& ls) {
  const auto& parsers = load_parsers();
  std::vector<std::string> kinds;
  for (const auto& [kind, parser] : parsers) kinds.push_back(kind);
  if (!ls.IsSequence()) {
    error(ls, "loads", "expected a list of {type: point | edge | pressure | gas | gravity, ...}");
    return;
  }
  for (size_t i = 0; i < ls.size(); ++i) {
    const Node l = ls[i];
    const std::string p = item("loads", i);
    if (!l.IsMap()) {
      check_map(l, p, {});
      continue;
    }
    auto type = text(l, "type", p, true);
    if (!type) continue;
    const auto it = std::find_if(parsers.begin(), parsers.end(),
                                 [&](const auto& kp) { return kp.first == *type; });
    if (it != parsers.end())
      (this->*(it->second))(l, p);
    else
      error(l["type"], sub(p, "type"),
            fmt::format("unknown load type '{}'{}", *type, suggestion(*type, kinds)));
  }
}

void Reader::parse_point_load(const Node& l, const std::string& p) {
  check_map(l, p, {"type", "nodes", "force", "function"});
  auto nodes = nodes_of(l, "nodes", p);
  auto f = vec3(l, "force", p, true);
  const int fn = function_ref(l, p);
  if (nodes && f) add_load(make_load(PointLoad{std::move(*nodes), *f, fn}), l, p);
}

void Reader::parse_edge_load(const Node& l, const std::string& p) {
  check_map(l, p, {"type", "nodes", "force_per_length", "function"});
  auto nodes = nodes_of(l, "nodes", p);
  auto f = vec3(l, "force_per_length", p, true);
  const int fn = function_ref(l, p);
  if (nodes && f) {
    EdgeLoad load;
    load.nodes = std::move(*nodes);
    load.force_per_length = *f;
    load.function = fn;
    add_load(make_load(std::move(load)), l["nodes"], sub(p, "nodes"));
  }
}

void Reader::parse_gravity_load(const Node& l, const std::string& p) {
  check_map(l, p, {"type", "acceleration", "function"});
  auto g = vec3(l, "acceleration", p, true);
  const int fn = function_ref(l, p);
  if (g) add_load(make_load(GravityLoad{*g, fn}), l, p);
}

void Reader::parse_pressure_load(const Node& l, const std::string& p) {
  check_map(l, p, {"type", "elements", "value", "function", "direction", "per"});
  auto set = text(l, "elements", p, true);
  auto v = number(l, "value", p, true);
  const int fn = function_ref(l, p);
  // A fixed direction (snow, dead weight of ponding): per area projected normal to it
  // (`per: projected`, the default) or per current area (`per: area`).
  std::optional<Vec3> direction;
  bool projected = true;
  if (has(l, "direction")) {
    direction = vec3(l, "direction", p, true);
    if (direction && !(direction->norm() > 0)) {
      error(l["direction"], sub(p, "direction"), "the direction must be a non-zero vector");
      direction.reset();
    }
    if (!direction) return;
    direction->normalize();
  }
  if (has(l, "per")) {
    auto per = text(l, "per", p, true);
    if (!per) return;
    if (!direction) {
      error(l["per"], sub(p, "per"),
            "'per' needs a 'direction': a follower pressure acts on the current area");
      return;
    }
    if (*per != "projected" && *per != "area") {
      error(l["per"], sub(p, "per"),
            fmt::format("expected projected or area, not '{}'{}", *per,
                        suggestion(*per, {"projected", "area"})));
      return;
    }
    projected = *per == "projected";
  }
  if (!set || !v) return;
  auto sit = element_sets_.find(*set);
  if (sit == element_sets_.end()) {
    if (mesh_ok_)
      error(l["elements"], sub(p, "elements"),
            fmt::format("undefined element set '{}'{}", *set,
                        suggestion(*set, keys_of(element_sets_))));
    return;
  }
  if (sit->second.dimension != 2) {
    error(l["elements"], sub(p, "elements"),
          fmt::format("pressure acts on membranes; set '{}' holds cables", *set));
    return;
  }
  for (int b : set_blocks_[*set]) {
    PressureLoad pl;
    pl.block = b;
    pl.value = *v;
    pl.function = fn;
    if (direction) {
      pl.fixed_direction = true;
      pl.direction = *direction;
      pl.projected = projected;
    }
    pl.elements.resize(static_cast<size_t>(in_.model.blocks[b]->size()));
    for (size_t e = 0; e < pl.elements.size(); ++e) pl.elements[e] = static_cast<int>(e);
    add_load(make_load(std::move(pl)), l, p);
  }
}

}  // namespace velum::io::model_file
