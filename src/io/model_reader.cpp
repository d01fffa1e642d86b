#include "velum/io/model_reader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>

#include "velum/io/mesh_data.hpp"

namespace velum::io {

InputError::InputError(std::vector<std::string> messages)
    : std::runtime_error(messages.empty() ? std::string("bad input") : messages.front()),
      messages_(std::move(messages)) {}

int edit_distance(std::string_view a, std::string_view b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] =
          std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1] ? 1 : 0)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

namespace {

using YAML::Node;
using Keys = std::initializer_list<std::string_view>;

std::string nearest(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 1 << 30;
  for (const auto& c : candidates) {
    const int d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  if (candidates.empty()) return {};
  return fmt::format(" (did you mean '{}'?)", nearest(word, candidates));
}

template <class Map>
std::vector<std::string> keys_of(const Map& m) {
  std::vector<std::string> out;
  for (const auto& kv : m) out.push_back(kv.first);
  return out;
}

struct MaterialDef {
  std::string type;
  bool cable = false;
  std::optional<PlaneStressLaw> law;
  CableLaw cable_law;
  double density = 0;
  bool ok = false;
};

struct ElementSet {
  std::vector<ElementGroup> groups;
  bool from_file = false;
  int dimension = 2;
  bool has_section = false;
};

class Reader {
 public:
  explicit Reader(std::filesystem::path file) : file_(std::move(file)), name_(file_.string()) {
    in_.file = file_;
  }

  ModelInput read() {
    Node root;
    try {
      root = YAML::LoadFile(name_);
    } catch (const YAML::BadFile&) {
      throw InputError({fmt::format("{}: cannot open the model file", name_)});
    } catch (const YAML::ParserException& e) {
      throw InputError(
          {fmt::format("{}:{}: YAML syntax error: {}", name_, e.mark.line + 1, e.msg)});
    }
    if (!root.IsMap()) {
      throw InputError(
          {fmt::format("{}:{}: the model file must be a mapping of sections (mesh, "
                       "materials, sections, ...)",
                       name_, root.Mark().line + 1 > 0 ? root.Mark().line + 1 : 1)});
    }
    try {
      parse(root);
    } catch (const YAML::Exception& e) {
      error_at(e.mark.line, "", fmt::format("malformed entry: {}", e.msg));
    }
    if (!errors_.empty()) throw InputError(errors_);
    return std::move(in_);
  }

 private:
  // ---- diagnostics --------------------------------------------------------------------
  int line_of(const Node& n) const { return n.Mark().is_null() ? 0 : n.Mark().line + 1; }
  void error_at(int line0, const std::string& key, const std::string& text) {
    const std::string loc = line0 >= 0 ? fmt::format("{}:{}", name_, line0 + 1) : name_;
    errors_.push_back(key.empty() ? fmt::format("{}: {}", loc, text)
                                  : fmt::format("{}: {}: {}", loc, key, text));
  }
  void error(const Node& at, const std::string& key, const std::string& text) {
    error_at(at.Mark().is_null() ? -1 : at.Mark().line, key, text);
  }
  void warn(const Node& at, const std::string& key, const std::string& text) {
    in_.warnings.push_back(
        fmt::format("{}:{}: {}: {}", name_, std::max(line_of(at), 1), key, text));
  }

  static std::string sub(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
  }
  static std::string item(const std::string& path, size_t i) {
    return fmt::format("{}[{}]", path, i);
  }

  /// Reports keys of `map` not in `allowed`; false when `map` is not a mapping.
  bool check_map(const Node& map, const std::string& path, Keys allowed) {
    if (!map.IsMap()) {
      error(map, path, "expected a mapping of keys (key: value)");
      return false;
    }
    std::vector<std::string> valid(allowed.begin(), allowed.end());
    for (const auto& kv : map) {
      if (!kv.first.IsScalar()) {
        error(kv.first, path, "keys must be plain names");
        continue;
      }
      const std::string k = kv.first.Scalar();
      if (std::find(valid.begin(), valid.end(), k) == valid.end())
        error(kv.first, sub(path, k), "unknown key" + suggestion(k, valid));
    }
    return true;
  }

  bool has(const Node& map, const char* key) const { return map.IsMap() && map[key]; }

  bool require(const Node& map, const char* key, const std::string& path) {
    if (has(map, key)) return true;
    error(map, sub(path, key), "required key is missing");
    return false;
  }

  std::optional<double> number(const Node& n, const std::string& path) {
    double v = 0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) {
      error(n, path, "expected a number");
      return std::nullopt;
    }
    if (!std::isfinite(v)) {
      error(n, path, "expected a finite number");
      return std::nullopt;
    }
    return v;
  }
  /// Optional key: nullopt when absent or invalid (invalid values are reported).
  std::optional<double> number(const Node& map, const char* key, const std::string& path,
                               bool required) {
    if (!has(map, key)) {
      if (required) require(map, key, path);
      return std::nullopt;
    }
    return number(map[key], sub(path, key));
  }
  std::optional<double> positive(const Node& map, const char* key, const std::string& path,
                                 bool required, const char* what) {
    auto v = number(map, key, path, required);
    if (v && *v <= 0) {
      error(map[key], sub(path, key), fmt::format("{} must be positive (got {})", what, *v));
      return std::nullopt;
    }
    return v;
  }
  std::optional<double> non_negative(const Node& map, const char* key, const std::string& path,
                                     const char* what) {
    auto v = number(map, key, path, false);
    if (v && *v < 0) {
      error(map[key], sub(path, key), fmt::format("{} must not be negative (got {})", what, *v));
      return std::nullopt;
    }
    return v;
  }
  std::optional<long> integer(const Node& n, const std::string& path, const char* what) {
    long v = 0;
    if (!n.IsScalar() || !YAML::convert<long>::decode(n, v)) {
      error(n, path, fmt::format("expected an integer {}", what));
      return std::nullopt;
    }
    return v;
  }
  std::optional<std::string> text(const Node& map, const char* key, const std::string& path,
                                  bool required) {
    if (!has(map, key)) {
      if (required) require(map, key, path);
      return std::nullopt;
    }
    const Node n = map[key];
    if (!n.IsScalar()) {
      error(n, sub(path, key), "expected a name (a plain string)");
      return std::nullopt;
    }
    return n.Scalar();
  }
  std::optional<bool> boolean(const Node& map, const char* key, const std::string& path) {
    if (!has(map, key)) return std::nullopt;
    bool v = false;
    if (!map[key].IsScalar() || !YAML::convert<bool>::decode(map[key], v)) {
      error(map[key], sub(path, key), "expected true or false");
      return std::nullopt;
    }
    return v;
  }
  std::optional<Vec3> vec3(const Node& n, const std::string& path) {
    if (!n.IsSequence() || n.size() != 3) {
      error(n, path, "expected a list of three numbers [x, y, z]");
      return std::nullopt;
    }
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
      auto c = number(n[i], item(path, i));
      if (!c) return std::nullopt;
      v[i] = *c;
    }
    return v;
  }
  std::optional<Vec3> vec3(const Node& map, const char* key, const std::string& path,
                           bool required) {
    if (!has(map, key)) {
      if (required) require(map, key, path);
      return std::nullopt;
    }
    return vec3(map[key], sub(path, key));
  }
  std::optional<int> component(const Node& map, const char* key, const std::string& path) {
    auto c = text(map, key, path, true);
    if (!c) return std::nullopt;
    if (*c == "x") return 0;
    if (*c == "y") return 1;
    if (*c == "z") return 2;
    error(map[key], sub(path, key),
          fmt::format("unknown component '{}'{}", *c, suggestion(*c, {"x", "y", "z"})));
    return std::nullopt;
  }

  // ---- sections of the file ------------------------------------------------------------
  void parse(const Node& root) {
    check_map(root, "",
              {"title", "mesh", "materials", "sections", "masses", "boundary", "loads", "functions",
               "analysis", "output"});
    if (auto t = text(root, "title", "", false)) in_.title = *t;
    parse_functions(root["functions"]);
    if (require(root, "mesh", "")) parse_mesh(root["mesh"]);
    if (require(root, "materials", "")) parse_materials(root["materials"]);
    if (require(root, "sections", "")) parse_sections(root["sections"]);
    if (has(root, "masses")) parse_masses(root["masses"]);
    if (has(root, "boundary")) parse_boundary(root["boundary"]);
    if (has(root, "loads")) parse_loads(root["loads"]);
    if (require(root, "analysis", "")) parse_analysis(root["analysis"]);
    parse_output(root["output"], root);
    final_checks(root);
  }

  void parse_functions(const Node& fs) {
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
  int function_ref(const Node& map, const std::string& path) {
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

  // ---- mesh -----------------------------------------------------------------------------
  void add_node(long id, const Vec3& x, const Node& at, const std::string& path) {
    if (in_.model.node_index.count(id)) {
      error(at, path, fmt::format("duplicate node id {}", id));
      return;
    }
    in_.model.add_node(id, x);
  }

  void parse_mesh(const Node& mesh) {
    if (!check_map(mesh, "mesh", {"file", "nodes", "elements", "node_sets"})) return;
    mesh_ok_ = true;
    if (!has(mesh, "file") && !has(mesh, "nodes")) {
      error(mesh, "mesh", "give a mesh file (mesh.file) or inline nodes (mesh.nodes)");
      mesh_ok_ = false;
      return;
    }
    long max_element_id = 0;
    if (auto f = text(mesh, "file", "mesh", false)) {
      std::filesystem::path p = *f;
      if (p.is_relative()) p = file_.parent_path() / p;
      try {
        MeshData m = read_gmsh(p);
        for (const auto& n : m.nodes) add_node(n.id, n.x, mesh["file"], "mesh.file");
        for (auto& g : m.groups) {
          for (long id : g.ids) max_element_id = std::max(max_element_id, id);
          auto& set = element_sets_[g.set];
          set.from_file = true;
          set.dimension = is_membrane_type(g.type) ? 2 : 1;
          set.groups.push_back(std::move(g));
        }
        for (auto& [name, ids] : m.node_sets) file_node_sets_[name] = std::move(ids);
      } catch (const MeshFileError& e) {
        error(mesh["file"], "mesh.file", e.what());
        mesh_ok_ = false;
      }
    }
    if (has(mesh, "nodes")) {
      const Node nodes = mesh["nodes"];
      if (!nodes.IsSequence()) {
        error(nodes, "mesh.nodes", "expected a list of [id, x, y, z]");
        mesh_ok_ = false;
      } else {
        for (size_t i = 0; i < nodes.size(); ++i) {
          const Node n = nodes[i];
          const std::string p = item("mesh.nodes", i);
          if (!n.IsSequence() || n.size() != 4) {
            error(n, p, "expected [id, x, y, z]");
            mesh_ok_ = false;
            continue;
          }
          auto id = integer(n[0], p, "node id");
          auto x = number(n[1], p), y = number(n[2], p), z = number(n[3], p);
          if (!id || !x || !y || !z) {
            mesh_ok_ = false;
            continue;
          }
          add_node(*id, Vec3(*x, *y, *z), n, p);
        }
      }
    }
    if (has(mesh, "elements")) parse_inline_elements(mesh["elements"], max_element_id);
    // Node sets: those of the mesh file, then inline ones (which may not collide).
    for (auto& [name, ids] : file_node_sets_) {
      std::vector<int> idx;
      for (long id : ids)
        if (auto it = in_.model.node_index.find(id); it != in_.model.node_index.end())
          idx.push_back(it->second);
      node_sets_[name] = std::move(idx);
    }
    if (has(mesh, "node_sets")) {
      const Node ns = mesh["node_sets"];
      if (!ns.IsMap()) {
        error(ns, "mesh.node_sets", "expected a mapping of name: [ids] or name: {box: [...]}");
      } else {
        for (const auto& kv : ns) {
          const std::string name = kv.first.Scalar();
          const std::string p = sub("mesh.node_sets", name);
          if (node_sets_.count(name)) {
            error(kv.first, p,
                  fmt::format("node set '{}' is already defined by the mesh file", name));
            continue;
          }
          if (kv.second.IsMap() && !kv.second["box"]) {
            check_map(kv.second, p, {"box"});
            continue;
          }
          if (auto nodes = node_list(kv.second, p, false)) node_sets_[name] = std::move(*nodes);
        }
      }
    }
  }

  void parse_inline_elements(const Node& els, long max_file_id) {
    if (!els.IsSequence()) {
      error(els, "mesh.elements", "expected a list of {set, type, connectivity}");
      return;
    }
    long next_id = max_file_id + 1;
    for (size_t i = 0; i < els.size(); ++i) {
      const Node e = els[i];
      const std::string p = item("mesh.elements", i);
      if (!check_map(e, p, {"set", "type", "connectivity", "ids"})) continue;
      auto set = text(e, "set", p, true);
      auto type = text(e, "type", p, true);
      if (!require(e, "connectivity", p) || !set || !type) continue;
      const int nn = nodes_of_type(*type);
      if (nn == 0) {
        error(e["type"], sub(p, "type"),
              fmt::format("unknown element type '{}'{}", *type,
                          suggestion(*type, {"tri3", "tri6", "quad4", "quad8", "quad9", "cable2",
                                             "cable3"})));
        continue;
      }
      const Node conn = e["connectivity"];
      const std::string cp = sub(p, "connectivity");
      if (!conn.IsSequence()) {
        error(conn, cp, "expected a list of node-id lists");
        continue;
      }
      ElementGroup g{*set, *type, {}, {}, line_of(e)};
      std::vector<long> ids;
      if (has(e, "ids")) {
        const Node in = e["ids"];
        if (!in.IsSequence() || in.size() != conn.size()) {
          error(in, sub(p, "ids"), "expected one element id per connectivity entry");
          continue;
        }
        for (size_t k = 0; k < in.size(); ++k)
          if (auto id = integer(in[k], sub(p, "ids"), "element id")) ids.push_back(*id);
      }
      bool ok = true;
      for (size_t k = 0; k < conn.size(); ++k) {
        const Node c = conn[k];
        const std::string ckp = item(cp, k);
        if (!c.IsSequence() || static_cast<int>(c.size()) != nn) {
          error(c, ckp,
                fmt::format("a {} element needs {} node ids, got {}", *type, nn,
                            c.IsSequence() ? std::to_string(c.size()) : "no list"));
          ok = false;
          continue;
        }
        const long eid = k < ids.size() ? ids[k] : next_id++;
        for (size_t j = 0; j < c.size(); ++j) {
          auto id = integer(c[j], ckp, "node id");
          if (!id) {
            ok = false;
            break;
          }
          if (!in_.model.node_index.count(*id)) {
            error(c[j], ckp, fmt::format("element {} refers to undefined node {}", eid, *id));
            ok = false;
          }
          g.node_ids.push_back(*id);
        }
        if (!element_ids_.insert(eid).second) {
          error(c, ckp, fmt::format("duplicate element id {}", eid));
          ok = false;
        }
        g.ids.push_back(eid);
      }
      if (!ok) {
        mesh_ok_ = false;
        continue;
      }
      auto& set_ref = element_sets_[*set];
      if (set_ref.from_file) {
        error(e["set"], sub(p, "set"),
              fmt::format("element set '{}' is already defined by the mesh file", *set));
        continue;
      }
      set_ref.dimension = is_membrane_type(*type) ? 2 : 1;
      set_ref.groups.push_back(std::move(g));
    }
  }

  /// Node indices from a node reference: an id, a list of ids, a set name or {box: [...]}.
  std::optional<std::vector<int>> node_list(const Node& n, const std::string& path,
                                            bool allow_names) {
    std::vector<int> out;
    auto by_id = [&](const Node& v) -> bool {
      auto id = integer(v, path, "node id");
      if (!id) return false;
      auto it = in_.model.node_index.find(*id);
      if (it == in_.model.node_index.end()) {
        error(v, path, fmt::format("undefined node {}", *id));
        return false;
      }
      out.push_back(it->second);
      return true;
    };
    if (n.IsSequence()) {
      if (n.size() == 0) {
        error(n, path, "the node list is empty");
        return std::nullopt;
      }
      for (size_t i = 0; i < n.size(); ++i)
        if (!by_id(n[i])) return std::nullopt;
      return out;
    }
    if (n.IsMap()) {
      if (!check_map(n, path, {"box"}) || !require(n, "box", path)) return std::nullopt;
      const Node b = n["box"];
      if (!b.IsSequence() || b.size() != 6) {
        error(b, sub(path, "box"), "expected [xmin, ymin, zmin, xmax, ymax, zmax]");
        return std::nullopt;
      }
      double v[6];
      for (int i = 0; i < 6; ++i) {
        auto c = number(b[i], sub(path, "box"));
        if (!c) return std::nullopt;
        v[i] = *c;
      }
      const Vec3 lo(v[0], v[1], v[2]), hi(v[3], v[4], v[5]);
      if ((hi - lo).minCoeff() < 0) {
        error(b, sub(path, "box"), "the box has a maximum below its minimum");
        return std::nullopt;
      }
      const auto& X = in_.model.X;
      const double tol =
          1e-9 *
          std::max(1.0, X.cols() ? (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm() : 1.0);
      for (int i = 0; i < in_.model.num_nodes(); ++i)
        if (((X.col(i) - lo).array() >= -tol).all() && ((hi - X.col(i)).array() >= -tol).all())
          out.push_back(i);
      if (out.empty()) {
        error(b, sub(path, "box"), "the box contains no node");
        return std::nullopt;
      }
      return out;
    }
    if (!n.IsScalar()) {
      error(n, path, "expected a node id, a list of node ids or a node set name");
      return std::nullopt;
    }
    long id = 0;
    if (YAML::convert<long>::decode(n, id)) {
      if (!by_id(n)) return std::nullopt;
      return out;
    }
    if (!allow_names) {
      error(n, path, "expected a list of node ids or {box: [...]}");
      return std::nullopt;
    }
    const std::string name = n.Scalar();
    if (auto it = node_sets_.find(name); it != node_sets_.end()) {
      if (it->second.empty()) {
        error(n, path, fmt::format("node set '{}' is empty", name));
        return std::nullopt;
      }
      return it->second;
    }
    if (auto it = element_sets_.find(name); it != element_sets_.end()) {
      std::set<int> nodes;
      for (const auto& g : it->second.groups)
        for (long id2 : g.node_ids) nodes.insert(in_.model.node_index.at(id2));
      return std::vector<int>(nodes.begin(), nodes.end());
    }
    auto names = keys_of(node_sets_);
    for (const auto& kv : element_sets_) names.push_back(kv.first);
    if (mesh_ok_)
      error(n, path, fmt::format("undefined node set '{}'{}", name, suggestion(name, names)));
    return std::nullopt;
  }

  std::optional<std::vector<int>> nodes_of(const Node& map, const char* key,
                                           const std::string& path) {
    if (!require(map, key, path)) return std::nullopt;
    return node_list(map[key], sub(path, key), true);
  }

  // ---- materials ------------------------------------------------------------------------
  void parse_materials(const Node& ms) {
    if (!ms.IsMap() || ms.size() == 0) {
      error(ms, "materials", "expected a mapping of name: {type: ..., ...}");
      return;
    }
    const std::vector<std::string> types = {"isotropic", "orthotropic", "anisotropic",
                                            "fibers",    "matrix",      "cable"};
    for (const auto& kv : ms) {
      const std::string name = kv.first.Scalar();
      const std::string p = sub("materials", name);
      const Node m = kv.second;
      MaterialDef def;
      materials_[name] = def;  // defined, even if invalid (no cascade of "undefined")
      if (!m.IsMap()) {
        error(m, p, "expected a mapping {type: ..., ...}");
        continue;
      }
      auto type = text(m, "type", p, true);
      if (!type) continue;
      def.type = *type;
      try {
        if (*type == "isotropic") {
          check_map(m, p, {"type", "E", "nu", "density"});
          auto E = positive(m, "E", p, true, "Young's modulus E");
          auto nu = number(m, "nu", p, true);
          if (nu && (*nu <= -1 || *nu >= 0.5)) {
            error(m["nu"], sub(p, "nu"),
                  fmt::format("Poisson's ratio must lie in (-1, 0.5) for a stable isotropic "
                              "sheet (got {})",
                              *nu));
            nu.reset();
          }
          if (E && nu) def.law = PlaneStressLaw::isotropic(name, *E, *nu);
        } else if (*type == "orthotropic" || *type == "anisotropic") {
          const bool aniso = *type == "anisotropic";
          if (aniso)
            check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "eta1", "eta2", "density"});
          else
            check_map(m, p, {"type", "E1", "E2", "nu12", "G12", "density"});
          AnisotropicConstants c;
          auto E1 = positive(m, "E1", p, true, "E1");
          auto E2 = positive(m, "E2", p, true, "E2");
          auto nu12 = number(m, "nu12", p, true);
          bool ok = E1 && E2 && nu12;
          if (has(m, "G12") && m["G12"].IsScalar() && m["G12"].Scalar() == "firt") {
            c.use_firt = true;
          } else if (auto G = positive(m, "G12", p, true, "the shear modulus G12")) {
            c.G12 = *G;
          } else {
            ok = false;
          }
          if (ok && nu12 && *nu12 < 0 && c.use_firt) {
            error(m["nu12"], sub(p, "nu12"), "Firt's shear modulus needs nu12 >= 0");
            ok = false;
          }
          if (aniso) {
            auto e1 = number(m, "eta1", p, false), e2 = number(m, "eta2", p, false);
            c.eta1 = e1.value_or(0);
            c.eta2 = e2.value_or(0);
          }
          if (ok) {
            c.E1 = *E1, c.E2 = *E2, c.nu12 = *nu12;
            def.law =
                aniso ? PlaneStressLaw::anisotropic(name, c)
                      : PlaneStressLaw::orthotropic(name, c.E1, c.E2, c.nu12, c.G12, c.use_firt);
          }
        } else if (*type == "fibers") {
          check_map(m, p, {"type", "fibers", "density"});
          if (require(m, "fibers", p)) {
            const Node fs = m["fibers"];
            const std::string fp = sub(p, "fibers");
            std::vector<FiberFamily> fams;
            bool ok = fs.IsSequence() && fs.size() > 0;
            if (!ok) error(fs, fp, "expected a list of {E, angle}");
            for (size_t i = 0; ok && i < fs.size(); ++i) {
              const std::string ip = item(fp, i);
              if (!check_map(fs[i], ip, {"E", "angle"})) {
                ok = false;
                break;
              }
              auto E = positive(fs[i], "E", ip, true, "the fibre modulus E");
              auto a = number(fs[i], "angle", ip, true);
              if (!E || !a)
                ok = false;
              else
                fams.push_back({*E, *a});
            }
            if (ok) def.law = PlaneStressLaw::fibers(name, fams);
          }
        } else if (*type == "matrix") {
          check_map(m, p, {"type", "Q", "density"});
          if (require(m, "Q", p)) {
            const Node q = m["Q"];
            Mat3 Q;
            bool ok = q.IsSequence() && q.size() == 3;
            for (size_t i = 0; ok && i < 3; ++i) {
              ok = q[i].IsSequence() && q[i].size() == 3;
              for (size_t j = 0; ok && j < 3; ++j) {
                auto v = number(q[i][j], sub(p, "Q"));
                if (!v)
                  ok = false;
                else
                  Q(static_cast<int>(i), static_cast<int>(j)) = *v;
              }
            }
            if (!ok)
              error(q, sub(p, "Q"), "expected a 3x3 matrix [[..], [..], [..]]");
            else if ((Q - Q.transpose()).cwiseAbs().maxCoeff() > 1e-12 * Q.cwiseAbs().maxCoeff())
              error(q, sub(p, "Q"), "the stiffness matrix Q must be symmetric");
            else
              def.law = PlaneStressLaw::matrix(name, Q);
          }
        } else if (*type == "cable") {
          check_map(m, p, {"type", "E", "density", "compression"});
          def.cable = true;
          if (auto E = positive(m, "E", p, true, "Young's modulus E")) def.cable_law.E = *E;
          def.cable_law.compression = boolean(m, "compression", p).value_or(false);
        } else {
          error(m["type"], sub(p, "type"),
                fmt::format("unknown material type '{}'{}", *type, suggestion(*type, types)));
          continue;
        }
      } catch (const MaterialError& e) {
        error(m, p, e.what());
        continue;
      } catch (const std::invalid_argument& e) {
        error(m, p, e.what());
        continue;
      }
      auto rho = number(m, "density", p, true);
      if (rho && *rho < 0) {
        error(m["density"], sub(p, "density"),
              fmt::format("the density must not be negative (got {})", *rho));
        rho.reset();
      }
      if (rho) def.density = *rho;
      def.ok = rho.has_value() && (def.cable ? def.cable_law.E > 0 : def.law.has_value());
      materials_[name] = def;
      in_.materials.push_back({name, *type});
    }
  }

  // ---- sections and blocks ----------------------------------------------------------------
  void parse_sections(const Node& ss) {
    if (!ss.IsSequence()) {
      error(ss, "sections", "expected a list of {elements, material, ...}");
      return;
    }
    for (size_t i = 0; i < ss.size(); ++i) {
      const Node s = ss[i];
      const std::string p = item("sections", i);
      if (!check_map(s, p, {"elements", "material", "thickness", "area", "axes", "integration"}))
        continue;
      auto set = text(s, "elements", p, true);
      auto mat = text(s, "material", p, true);
      if (!set || !mat) continue;
      auto sit = element_sets_.find(*set);
      if (sit == element_sets_.end()) {
        if (mesh_ok_)
          error(s["elements"], sub(p, "elements"),
                fmt::format("undefined element set '{}'{}", *set,
                            suggestion(*set, keys_of(element_sets_))));
        continue;
      }
      ElementSet& es = sit->second;
      if (es.has_section) {
        error(s["elements"], sub(p, "elements"),
              fmt::format("element set '{}' already has a section", *set));
        continue;
      }
      es.has_section = true;
      auto mit = materials_.find(*mat);
      if (mit == materials_.end()) {
        error(
            s["material"], sub(p, "material"),
            fmt::format("undefined material '{}'{}", *mat, suggestion(*mat, keys_of(materials_))));
        continue;
      }
      const MaterialDef& md = mit->second;
      const bool membrane = es.dimension == 2;
      if (membrane && md.cable) {
        error(s["material"], sub(p, "material"),
              fmt::format("set '{}' holds membrane elements but material '{}' is a cable law", *set,
                          *mat));
        continue;
      }
      if (!membrane && !md.cable && !md.type.empty()) {
        error(s["material"], sub(p, "material"),
              fmt::format("set '{}' holds cable elements but material '{}' is a membrane law "
                          "(use type: cable)",
                          *set, *mat));
        continue;
      }
      std::optional<double> size;
      if (membrane) {
        if (has(s, "area"))
          error(s["area"], sub(p, "area"), "membranes take a thickness, not an area");
        size = positive(s, "thickness", p, true, "the thickness");
      } else {
        if (has(s, "thickness"))
          error(s["thickness"], sub(p, "thickness"), "cables take an area, not a thickness");
        if (has(s, "axes")) error(s["axes"], sub(p, "axes"), "cables take no axes");
        size = positive(s, "area", p, true, "the cross-section area");
      }
      std::optional<SheetAxes> axes;
      bool axes_ok = true;
      if (membrane && has(s, "axes")) {
        axes = parse_axes(s["axes"], sub(p, "axes"));
        axes_ok = axes.has_value();
      }
      auto integration = shape::Integration::kGauss;
      bool integration_ok = true;
      if (has(s, "integration")) {
        const auto how = text(s, "integration", p, true);
        if (how && *how == "nodal")
          integration = shape::Integration::kNodal;
        else if (how && *how != "gauss") {
          error(s["integration"], sub(p, "integration"),
                fmt::format("unknown integration '{}' (gauss | nodal)", *how));
          integration_ok = false;
        } else if (!how)
          integration_ok = false;
      }
      if (!size || !md.ok || !axes_ok || !integration_ok || !mesh_ok_) continue;
      build_blocks(*set, es, md, *size, axes ? &*axes : nullptr, integration, s, p);
    }
  }

  std::optional<SheetAxes> parse_axes(const Node& a, const std::string& p) {
    if (!check_map(a, p, {"points"}) || !require(a, "points", p)) return std::nullopt;
    const Node pts = a["points"];
    const std::string pp = sub(p, "points");
    if (!pts.IsSequence() || pts.size() != 3) {
      error(pts, pp, "expected three points [P1, P2, P3] (node ids or [x, y, z])");
      return std::nullopt;
    }
    Vec3 P[3];
    for (size_t i = 0; i < 3; ++i) {
      if (pts[i].IsSequence()) {
        auto v = vec3(pts[i], item(pp, i));
        if (!v) return std::nullopt;
        P[i] = *v;
      } else {
        auto id = integer(pts[i], item(pp, i), "node id or [x, y, z]");
        if (!id) return std::nullopt;
        auto it = in_.model.node_index.find(*id);
        if (it == in_.model.node_index.end()) {
          error(pts[i], item(pp, i), fmt::format("undefined node {}", *id));
          return std::nullopt;
        }
        P[i] = in_.model.X.col(it->second);
      }
    }
    try {
      return axes_from_points(P[0], P[1], P[2]);
    } catch (const std::invalid_argument& e) {
      error(pts, pp, fmt::format("the points do not define a plane: {}", e.what()));
      return std::nullopt;
    }
  }

  void build_blocks(const std::string& set, const ElementSet& es, const MaterialDef& md,
                    double size, const SheetAxes* axes, shape::Integration integration,
                    const Node& at, const std::string& p) {
    for (const auto& g : es.groups) {
      std::vector<int> conn;
      conn.reserve(g.node_ids.size());
      bool ok = true;
      for (long id : g.node_ids) {
        auto it = in_.model.node_index.find(id);
        if (it == in_.model.node_index.end()) {
          error(at, p, fmt::format("set '{}' refers to undefined node {}", set, id));
          ok = false;
          break;
        }
        conn.push_back(it->second);
      }
      if (!ok) continue;
      BlockSetupReport report;
      std::unique_ptr<ElementBlock> block;
      try {
        if (md.cable)
          block = make_cable_block(g.type, set, std::move(conn), in_.model.X, md.cable_law,
                                   md.density, size, integration, report);
        else
          block = make_membrane_block(g.type, set, std::move(conn), in_.model.X, *md.law,
                                      md.density, size, axes, integration, report);
      } catch (const std::exception& e) {
        error(at, p, fmt::format("set '{}': {}", set, e.what()));
        continue;
      }
      const std::string where = g.line > 0 ? fmt::format("{}:{}", name_, g.line)
                                           : fmt::format("{}:{}", name_, line_of(at));
      if (report.worst_element >= 0 && !(report.worst_jacobian > 0)) {
        const long eid = g.ids[static_cast<size_t>(report.worst_element)];
        errors_.push_back(
            md.cable ? fmt::format("{}: {}: element {} of set '{}' has zero length", where,
                                   g.line > 0 ? "mesh.elements" : p, eid, set)
                     : fmt::format("{}: {}: element {} of set '{}' is degenerate or inverted "
                                   "(reference Jacobian {:.3g} <= 0)",
                                   where, g.line > 0 ? "mesh.elements" : p, eid, set,
                                   report.worst_jacobian));
        continue;
      }
      if (report.poor_axes_element >= 0 && report.poor_axes_quality < 0.5)
        warn(at, p,
             fmt::format("set '{}': the sheet axes project poorly onto element {} (quality "
                         "{:.2f}): the sheet is far from the plane of the axes points",
                         set, g.ids[static_cast<size_t>(report.poor_axes_element)],
                         report.poor_axes_quality));
      set_blocks_[set].push_back(static_cast<int>(in_.model.blocks.size()));
      block_ids_.push_back(g.ids);
      in_.model.blocks.push_back(std::move(block));
    }
  }

  // ---- masses, boundary, loads --------------------------------------------------------------
  void parse_masses(const Node& ms) {
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
      for (int n : *nodes) in_.model.masses.push_back({n, *mass, rho, cda});
    }
  }

  void parse_boundary(const Node& bs) {
    if (!bs.IsSequence()) {
      error(bs, "boundary", "expected a list of {nodes, fix | displacement | symmetry}");
      return;
    }
    for (size_t i = 0; i < bs.size(); ++i) {
      const Node b = bs[i];
      const std::string p = item("boundary", i);
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
          f.nodes = std::move(*nodes);
          in_.model.fixed.push_back(std::move(f));
        }
      } else if (has(b, "displacement")) {
        auto d = vec3(b, "displacement", p, true);
        const int fn = function_ref(b, p);
        if (d && nodes) in_.model.prescribed.push_back({std::move(*nodes), *d, fn});
      } else {
        const Node s = b["symmetry"];
        const std::string sp = sub(p, "symmetry");
        if (!check_map(s, sp, {"normal"})) continue;
        auto n = vec3(s, "normal", sp, true);
        if (n && n->norm() == 0) {
          error(s["normal"], sub(sp, "normal"), "the plane normal must not be zero");
          n.reset();
        }
        if (n && nodes) in_.model.symmetry.push_back({std::move(*nodes), n->normalized()});
      }
    }
  }

  void parse_loads(const Node& ls) {
    if (!ls.IsSequence()) {
      error(ls, "loads", "expected a list of {type: point | edge | pressure | gravity, ...}");
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
      if (*type == "point") {
        check_map(l, p, {"type", "nodes", "force", "function"});
        auto nodes = nodes_of(l, "nodes", p);
        auto f = vec3(l, "force", p, true);
        const int fn = function_ref(l, p);
        if (nodes && f) in_.model.point_loads.push_back({std::move(*nodes), *f, fn});
      } else if (*type == "edge") {
        check_map(l, p, {"type", "nodes", "force_per_length", "function"});
        auto nodes = nodes_of(l, "nodes", p);
        auto f = vec3(l, "force_per_length", p, true);
        const int fn = function_ref(l, p);
        if (nodes && f) {
          in_.model.edge_loads.push_back({std::move(*nodes), *f, fn});
          edge_load_nodes_.push_back({l["nodes"], sub(p, "nodes")});
        }
      } else if (*type == "pressure") {
        check_map(l, p, {"type", "elements", "value", "function"});
        auto set = text(l, "elements", p, true);
        auto v = number(l, "value", p, true);
        const int fn = function_ref(l, p);
        if (!set || !v) continue;
        auto sit = element_sets_.find(*set);
        if (sit == element_sets_.end()) {
          if (mesh_ok_)
            error(l["elements"], sub(p, "elements"),
                  fmt::format("undefined element set '{}'{}", *set,
                              suggestion(*set, keys_of(element_sets_))));
          continue;
        }
        if (sit->second.dimension != 2) {
          error(l["elements"], sub(p, "elements"),
                fmt::format("pressure acts on membranes; set '{}' holds cables", *set));
          continue;
        }
        for (int b : set_blocks_[*set]) {
          PressureLoad pl;
          pl.block = b;
          pl.value = *v;
          pl.function = fn;
          pl.elements.resize(static_cast<size_t>(in_.model.blocks[b]->size()));
          for (size_t e = 0; e < pl.elements.size(); ++e) pl.elements[e] = static_cast<int>(e);
          in_.model.pressures.push_back(std::move(pl));
        }
      } else if (*type == "gravity") {
        check_map(l, p, {"type", "acceleration", "function"});
        auto g = vec3(l, "acceleration", p, true);
        const int fn = function_ref(l, p);
        if (g) in_.model.gravity.push_back({*g, fn});
      } else {
        error(l["type"], sub(p, "type"),
              fmt::format("unknown load type '{}'{}", *type,
                          suggestion(*type, {"point", "edge", "pressure", "gravity"})));
      }
    }
  }

  // ---- analysis and output ----------------------------------------------------------------
  void parse_analysis(const Node& a) {
    if (!check_map(a, "analysis",
                   {"type", "integrator", "time", "newton", "damping", "linear_solver"}))
      return;
    AnalysisSettings& s = in_.analysis;
    if (auto t = text(a, "type", "analysis", false)) {
      if (*t == "static")
        s.type = AnalysisSettings::Type::kStatic;
      else if (*t == "dynamic")
        s.type = AnalysisSettings::Type::kDynamic;
      else
        error(
            a["type"], "analysis.type",
            fmt::format("unknown analysis type '{}'{}", *t, suggestion(*t, {"static", "dynamic"})));
    }
    if (has(a, "integrator")) {
      const Node in = a["integrator"];
      const std::string p = "analysis.integrator";
      if (check_map(in, p, {"scheme", "rho_inf", "alpha", "beta", "gamma"})) {
        if (auto sc = text(in, "scheme", p, false)) {
          const std::vector<std::string> schemes = {"newmark", "hht", "generalized-alpha",
                                                    "central-difference"};
          if (std::find(schemes.begin(), schemes.end(), *sc) == schemes.end())
            error(in["scheme"], sub(p, "scheme"),
                  fmt::format("unknown scheme '{}'{}", *sc, suggestion(*sc, schemes)));
          else
            s.scheme = *sc;
          if (*sc == "central-difference" && s.type == AnalysisSettings::Type::kStatic)
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
        if (step && end && *end / *step > 1e9)
          error(t["step"], sub(p, "step"), "more than 1e9 steps: the step is too small for end");
        if (auto ad = boolean(t, "adaptive", p)) s.time.adaptive = *ad;
      }
    }
    if (has(a, "newton")) {
      const Node n = a["newton"];
      const std::string p = "analysis.newton";
      if (check_map(n, p, {"tolerance", "max_iterations", "line_search", "reuse_tangent"})) {
        if (auto tol = positive(n, "tolerance", p, false, "the Newton tolerance"))
          s.newton.tolerance = *tol;
        if (has(n, "max_iterations")) {
          auto it = integer(n["max_iterations"], sub(p, "max_iterations"), "count");
          if (it && *it < 1)
            error(n["max_iterations"], sub(p, "max_iterations"),
                  "at least one iteration is needed");
          else if (it)
            s.newton.max_iterations = static_cast<int>(*it);
        }
        if (auto ls = boolean(n, "line_search", p)) s.newton.line_search = *ls;
        if (auto reuse = boolean(n, "reuse_tangent", p)) s.newton.reuse_tangent = *reuse;
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
    if (auto ls = text(a, "linear_solver", "analysis", false)) {
      if (*ls == "petsc") {
        error(a["linear_solver"], "analysis.linear_solver",
              "the PETSc back-end is not available in this build (use auto, cholmod, umfpack, "
              "klu or mumps)");
      } else {
        try {
          s.solver = solver_kind_from_name(*ls);
          if (s.solver == SolverKind::kMumps && !have_mumps())
            error(a["linear_solver"], "analysis.linear_solver",
                  "this build has no MUMPS (install libmumps-seq-dev and rebuild, or use auto, "
                  "cholmod, umfpack or klu)");
        } catch (const std::invalid_argument&) {
          error(a["linear_solver"], "analysis.linear_solver",
                fmt::format(
                    "unknown linear solver '{}'{}", *ls,
                    suggestion(*ls, {"auto", "cholmod", "umfpack", "klu", "mumps", "petsc"})));
        }
      }
    }
  }

  void parse_output(const Node& o, const Node& root) {
    OutputSettings& out = in_.output;
    out.directory = file_.parent_path() / "out";
    out.interval = in_.analysis.time.step;
    if (!o) return;
    if (!check_map(o, "output", {"directory", "interval", "fields", "history"})) return;
    if (auto d = text(o, "directory", "output", false)) {
      std::filesystem::path p = *d;
      out.directory = p.is_relative() ? file_.parent_path() / p : p;
    }
    if (auto iv = positive(o, "interval", "output", false, "the output interval")) {
      out.interval = *iv;
      if (*iv < in_.analysis.time.min_step)
        error(o["interval"], "output.interval", "the output interval is shorter than min_step");
    }
    if (auto f = boolean(o, "fields", "output")) out.fields = *f;
    (void)root;
    if (!has(o, "history")) return;
    const Node h = o["history"];
    if (!h.IsSequence()) {
      error(h, "output.history", "expected a list of {name, quantity, ...}");
      return;
    }
    const std::vector<std::string> quantities = {
        "displacement", "velocity",       "position",      "reaction",     "fiber_angle_change",
        "stress",       "kinetic_energy", "strain_energy", "external_work"};
    std::set<std::string> names;
    for (size_t i = 0; i < h.size(); ++i) {
      const Node e = h[i];
      const std::string p = item("output.history", i);
      if (!check_map(e, p, {"name", "quantity", "node", "nodes", "component", "point", "unit"}))
        continue;
      auto name = text(e, "name", p, true);
      auto q = text(e, "quantity", p, true);
      if (!name || !q) continue;
      if (name->empty() || name->find_first_of(",\"\n") != std::string::npos) {
        error(e["name"], sub(p, "name"),
              "a column name must be non-empty, without commas or quotes");
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
            if (!locate(he)) {
              if (mesh_ok_)
                error(e["point"], sub(p, "point"),
                      fmt::format("the point [{}, {}, {}] lies in no membrane element",
                                  he.point.x(), he.point.y(), he.point.z()));
              ok = false;
            }
          }
          break;
        }
        default:
          break;
      }
      if (ok) out.history.push_back(std::move(he));
    }
  }

  bool locate(HistoryEntry& he) const {
    for (size_t b = 0; b < in_.model.blocks.size(); ++b) {
      const auto& blk = *in_.model.blocks[b];
      if (blk.kind() != ElementKind::kMembrane) continue;
      for (int e = 0; e < blk.size(); ++e)
        if (blk.locate(e, he.point, he.xi)) {
          he.block = static_cast<int>(b);
          he.element = e;
          return true;
        }
    }
    return false;
  }

  void final_checks(const Node& root) {
    for (const auto& [name, set] : element_sets_) {
      if (set.has_section) continue;
      if (set.from_file && set.dimension == 1) continue;  // a boundary curve: a node set only
      if (mesh_ok_)
        error(root["sections"] ? root["sections"] : root, "sections",
              fmt::format("element set '{}' has no section (material and {})", name,
                          set.dimension == 2 ? "thickness" : "area"));
    }
    if (!errors_.empty()) return;
    if (in_.model.blocks.empty()) {
      error(root, "mesh", "the model has no elements");
      return;
    }
    for (size_t i = 0; i < in_.model.edge_loads.size(); ++i) {
      const NodePositions F = edge_load_forces(in_.model, in_.model.edge_loads[i]);
      if (F.cwiseAbs().maxCoeff() == 0 && in_.model.edge_loads[i].force_per_length.norm() > 0)
        error(edge_load_nodes_[i].first, edge_load_nodes_[i].second,
              "no membrane boundary edge has all its nodes in this node set");
    }
    std::vector<char> used(static_cast<size_t>(in_.model.num_nodes()), 0);
    for (const auto& b : in_.model.blocks)
      for (int n : b->connectivity()) used[static_cast<size_t>(n)] = 1;
    int unused = 0;
    long first = 0;
    for (size_t n = 0; n < used.size(); ++n)
      if (!used[n]) {
        if (unused++ == 0) first = in_.model.node_ids[n];
      }
    if (unused > 0) {
      warn(root["mesh"], "mesh",
           fmt::format("{} node(s) belong to no element (first: node {}); they are fixed", unused,
                       first));
      FixedDofs f;
      f.fix = {true, true, true};
      for (size_t n = 0; n < used.size(); ++n)
        if (!used[n]) f.nodes.push_back(static_cast<int>(n));
      in_.model.fixed.push_back(std::move(f));
    }
  }

  std::filesystem::path file_;
  std::string name_;
  std::vector<std::string> errors_;
  ModelInput in_;
  bool mesh_ok_ = false;
  std::map<std::string, int> functions_;
  std::map<std::string, MaterialDef> materials_;
  std::map<std::string, ElementSet> element_sets_;
  std::map<std::string, std::vector<long>> file_node_sets_;
  std::map<std::string, std::vector<int>> node_sets_;
  std::map<std::string, std::vector<int>> set_blocks_;
  std::vector<std::vector<long>> block_ids_;
  std::vector<std::pair<Node, std::string>> edge_load_nodes_;
  std::set<long> element_ids_;
};

}  // namespace

ModelInput read_model(const std::filesystem::path& file) {
  return Reader(file).read();
}

}  // namespace velum::io
