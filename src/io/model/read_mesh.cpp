// Reads mesh: (nodes and elements from a Gmsh or Abaqus/CalculiX .inp file or inline, node
// sets).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reader.hpp"
#include "velum/io/inp_reader.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io::model_file {
namespace {
// A set's dimension: 2 for surface shapes, 1 otherwise.
int dimension_of(std::string_view type) {
  const shape::ShapeInfo* s = shape::find(type);
  return s && s->surface() ? 2 : 1;
}
}  // namespace

void Reader::add_node(long id, const Vec3& x, const Node& at, const std::string& path) {
  if (in_.model.node_index.count(id)) {
    error(at, path, fmt::format("duplicate node id {}", id));
    return;
  }
  in_.model.add_node(id, x);
}

void Reader::parse_mesh(const Node& mesh) {
  if (has(mesh, "parts")) {  // a split model: this process's part only (read_parts.cpp)
    parse_parts(mesh);
    return;
  }
  if (!check_map(mesh, "mesh",
                 {"file", "parts", "nodes", "elements", "node_sets", "positions",
                  "reference_positions", "panel_references"}))
    return;
  mesh_ok_ = true;
  if (!has(mesh, "file") && !has(mesh, "nodes")) {
    error(mesh, "mesh",
          "give a mesh file (mesh.file), inline nodes (mesh.nodes) or a split model's parts "
          "(mesh.parts)");
    mesh_ok_ = false;
    return;
  }
  long max_element_id = 0;
  if (auto f = text(mesh, "file", "mesh", false)) {
    std::filesystem::path p = *f;
    if (p.is_relative()) p = base_dir_ / p;
    try {
      std::string ext = p.extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      std::vector<std::string> notes;
      MeshData m = ext == ".inp" ? read_inp_mesh(p, notes) : read_gmsh(p);
      for (const auto& w : notes) warn(mesh["file"], "mesh.file", w);
      for (const auto& n : m.nodes) add_node(n.id, n.x, mesh["file"], "mesh.file");
      for (auto& g : m.groups) {
        for (long id : g.ids) max_element_id = std::max(max_element_id, id);
        auto& set = element_sets_[g.set];
        set.from_file = true;
        set.dimension = dimension_of(g.type);
        set.groups.push_back(std::move(g));
      }
      for (auto& [name, ids] : m.node_sets) file_node_sets_[name] = std::move(ids);
    } catch (const MeshFileError& e) {
      error(mesh["file"], "mesh.file", e.what());
      mesh_ok_ = false;
    } catch (const InpError& e) {
      for (const auto& m : e.messages()) error(mesh["file"], "mesh.file", m);
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
        const auto row = node_row(n, p);
        if (!row) {
          mesh_ok_ = false;
          continue;
        }
        add_node(row->first, row->second, n, p);
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
  in_.node_sets = node_sets_;  // velum seams writes them as lists
  // Positions that replace the mesh's coordinates (a found form: DIR/form.yaml), after the
  // node sets (boxes included) were found on the mesh's own coordinates.
  if (has(mesh, "positions")) {
    const Node ps = mesh["positions"];
    if (!ps.IsSequence()) {
      error(ps, "mesh.positions", "expected a list of [id, x, y, z]");
      return;
    }
    for (size_t i = 0; i < ps.size(); ++i) {
      const Node n = ps[i];
      const std::string p = item("mesh.positions", i);
      const auto row = node_row(n, p);
      if (!row) continue;
      auto it = in_.model.node_index.find(row->first);
      if (it == in_.model.node_index.end()) {
        error(n, p, fmt::format("node {} is not in the mesh", row->first));
        continue;
      }
      in_.model.X.col(it->second) = row->second;
    }
  }
  if (has(mesh, "reference_positions")) parse_reference_positions(mesh["reference_positions"]);
  if (has(mesh, "panel_references")) parse_panel_references(mesh["panel_references"]);
}

std::optional<std::pair<long, Vec3>> Reader::node_row(const Node& n, const std::string& p) {
  if (!n.IsSequence() || n.size() != 4) {
    error(n, p, "expected [id, x, y, z]");
    return std::nullopt;
  }
  auto id = integer(n[0], p, "node id");
  auto x = number(n[1], p), y = number(n[2], p), z = number(n[3], p);
  if (!id || !x || !y || !z) return std::nullopt;
  return std::pair{*id, Vec3(*x, *y, *z)};
}

// The stress-free coordinates of the listed nodes: the model's reference X becomes them and
// the start coordinates (the mesh's, or mesh.positions') the start displacement U0 = x − X, so
// that every element, law and load measures strain from the reference as before.
void Reader::parse_reference_positions(const Node& ps) {
  const std::string path = "mesh.reference_positions";
  if (!ps.IsSequence()) {
    error(ps, path, "expected a list of [id, x, y, z]");
    return;
  }
  Model& m = in_.model;
  NodePositions U0 = NodePositions::Zero(3, m.num_nodes());
  std::set<long> seen;
  for (size_t i = 0; i < ps.size(); ++i) {
    const Node n = ps[i];
    const std::string p = item(path, i);
    const auto row = node_row(n, p);
    if (!row) continue;
    const auto& [id, ref] = *row;
    auto it = m.node_index.find(id);
    if (it == m.node_index.end()) {
      error(n, p, fmt::format("node {} is not in the mesh", id));
      continue;
    }
    if (!seen.insert(id).second) {
      error(n, p, fmt::format("node {} is given a reference position twice", id));
      continue;
    }
    U0.col(it->second) = m.X.col(it->second) - ref;
    m.X.col(it->second) = ref;
  }
  if (U0.cwiseAbs().maxCoeff() > 0) m.U0 = std::move(U0);
}

void Reader::parse_inline_elements(const Node& els, long max_file_id) {
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
    if (*type == "sliding_cable") {
      parse_sliding_cables(e, *set, p, next_id);
      continue;
    }
    const shape::ShapeInfo* shape = shape::find(*type);
    if (!shape) {
      std::vector<std::string> names;
      for (const auto& s : shape::kShapeTable) names.emplace_back(s.name);
      names.emplace_back("sliding_cable");
      error(e["type"], sub(p, "type"),
            fmt::format("unknown element type '{}'{}", *type, suggestion(*type, names)));
      continue;
    }
    const int nn = shape->nodes;
    const Node conn = e["connectivity"];
    const std::string cp = sub(p, "connectivity");
    if (!conn.IsSequence()) {
      error(conn, cp, "expected a list of node-id lists");
      continue;
    }
    if (conn.size() == 0) {
      error(conn, cp, "the connectivity list is empty: give at least one element");
      mesh_ok_ = false;
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
      if (!read_element_nodes(c, ckp, eid, g.node_ids)) ok = false;
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
    set_ref.dimension = dimension_of(*type);
    set_ref.groups.push_back(std::move(g));
  }
}

/// Node indices from a node reference: an id, a list of ids, a set name or {box: [...]}.
std::optional<std::vector<int>> Reader::node_list(const Node& n, const std::string& path,
                                                  bool allow_names) {
  std::vector<int> out;
  auto by_id = [&](const Node& v) -> bool {
    auto id = integer(v, path, "node id");
    if (!id) return false;
    auto it = in_.model.node_index.find(*id);
    if (parts_given_)  // a part read: another part's node, or none's (checked over the parts)
      in_.part_ids.push_back({it != in_.model.node_index.end(),
                              fmt::format("{}:{}: {}: undefined node {} (in no part of mesh.parts)",
                                          name_, line_of(v), path, *id)});
    if (it == in_.model.node_index.end()) {
      if (parts_given_) return true;
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
        1e-9 * std::max(1.0, part_      ? part_->size  // the whole model's, as the split's
                             : X.cols() ? (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm()
                                        : 1.0);
    for (int i = 0; i < in_.model.num_nodes(); ++i)
      if (((X.col(i) - lo).array() >= -tol).all() && ((hi - X.col(i)).array() >= -tol).all())
        out.push_back(i);
    if (out.empty() && !part_) {  // (a part read: the box's nodes are another part's)
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
    if (it->second.empty() && !part_) {  // (a part read: the set's nodes are another part's)
      error(n, path, fmt::format("node set '{}' is empty", name));
      return std::nullopt;
    }
    return it->second;
  }
  if (part_)  // the element set's nodes here, all of them (not only those of own elements)
    if (auto it = part_set_nodes_.find(name); it != part_set_nodes_.end()) return it->second;
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

std::optional<std::vector<int>> Reader::nodes_of(const Node& map, const char* key,
                                                 const std::string& path) {
  if (!require(map, key, path)) return std::nullopt;
  return node_list(map[key], sub(path, key), true);
}

}  // namespace velum::io::model_file

namespace velum::io::model_file {

// One group (and later one block) per chain: chains differ in their node counts.
// An element's node ids (the list c) into `nodes`, each an integer naming a defined node;
// false, with the reason reported, where one is not.
bool Reader::read_element_nodes(const Node& c, const std::string& ckp, long eid,
                                std::vector<long>& nodes) {
  bool ok = true;
  for (size_t j = 0; j < c.size(); ++j) {
    auto id = integer(c[j], ckp, "node id");
    if (!id) return false;
    if (!in_.model.node_index.count(*id)) {
      error(c[j], ckp, fmt::format("element {} refers to undefined node {}", eid, *id));
      ok = false;
    }
    nodes.push_back(*id);
  }
  return ok;
}

void Reader::parse_sliding_cables(const Node& e, const std::string& set, const std::string& p,
                                  long& next_id) {
  const Node conn = e["connectivity"];
  const std::string cp = sub(p, "connectivity");
  if (!conn.IsSequence() || conn.size() == 0) {
    error(conn, cp, "expected a list of chains [[n1, n2, ..., nk]], one per cable");
    mesh_ok_ = false;
    return;
  }
  if (has(e, "ids")) {
    error(e["ids"], sub(p, "ids"), "sliding cables are numbered in order; ids are not read");
    mesh_ok_ = false;
    return;
  }
  auto& set_ref = element_sets_[set];
  for (size_t k = 0; k < conn.size(); ++k) {
    const Node c = conn[k];
    const std::string ckp = item(cp, k);
    if (!c.IsSequence() || c.size() < 3) {
      error(c, ckp,
            fmt::format("a sliding_cable chain runs through at least 3 nodes (2 segments), got "
                        "{}; a single segment is a cable2 element",
                        c.IsSequence() ? std::to_string(c.size()) : "no list"));
      mesh_ok_ = false;
      continue;
    }
    ElementGroup g{set, "sliding_cable", {}, {}, line_of(e)};
    const long eid = next_id++;
    bool ok = read_element_nodes(c, ckp, eid, g.node_ids);
    for (size_t j = 1; ok && j < g.node_ids.size(); ++j)
      if (g.node_ids[j] == g.node_ids[j - 1]) {
        error(c[j], ckp,
              fmt::format("node {} is repeated consecutively in the chain: a segment of zero "
                          "length",
                          g.node_ids[j]));
        ok = false;
      }
    if (!element_ids_.insert(eid).second) {
      error(c, ckp, fmt::format("duplicate element id {}", eid));
      ok = false;
    }
    if (!ok) {
      mesh_ok_ = false;
      continue;
    }
    g.ids.push_back(eid);
    set_ref.dimension = 1;
    set_ref.groups.push_back(std::move(g));
  }
}

}  // namespace velum::io::model_file
