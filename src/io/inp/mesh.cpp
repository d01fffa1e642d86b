// *NODE, *ELEMENT, *NSET and *ELSET: the mesh of a deck.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <set>

#include "model.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io::inp {
namespace {

// The Abaqus element types of the shape table (shape_info.hpp), in alphabetical order.
std::string type_list() {
  std::vector<std::string_view> names;
  for (const auto& t : shape::kShapeTable) {
    if (!t.abaqus.empty()) names.push_back(t.abaqus);
    if (!t.abaqus_reduced.empty()) names.push_back(t.abaqus_reduced);
  }
  std::sort(names.begin(), names.end());
  std::string s;
  for (const auto name : names) {
    if (!s.empty()) s += ' ';
    s += name;
  }
  return s;
}

Set& set_named(std::vector<Set>& sets, std::map<std::string, size_t>& at, const std::string& name,
               const Keyword& k) {
  const std::string key = canonical(name);
  if (auto it = at.find(key); it != at.end()) return sets[it->second];  // Abaqus appends
  at[key] = sets.size();
  sets.push_back({name, {}, k.file, k.line});
  return sets.back();
}

void add_ids(Set& s, const std::vector<long>& ids) {
  std::set<long> have(s.ids.begin(), s.ids.end());
  for (long id : ids)
    if (have.insert(id).second) s.ids.push_back(id);
}

/// The ids of a *NSET or *ELSET block: GENERATE triples, or ids and set names.
std::vector<long> set_members(const Keyword& k, bool nodes, const Mesh& mesh, Diagnostics& diag) {
  std::vector<long> ids;
  std::set<const Set*> merged;  // a set named twice in one block is merged once
  const char* what = nodes ? "node" : "element";
  const auto& known = nodes ? mesh.node_at : mesh.element_at;
  constexpr long kMaxGenerated = 100'000'000;
  for (const auto& d : k.data) {
    if (k.has("GENERATE")) {
      auto a = diag.integer(k, d, 0), b = diag.integer(k, d, 1), inc = diag.integer(k, d, 2, 1L);
      if (!a || !b || !inc) continue;
      if (*inc <= 0 || *b < *a || (*b - *a) / *inc > kMaxGenerated) {
        diag.error(k, d,
                   fmt::format("GENERATE needs first <= last and an increment > 0 (got {}, {}, "
                               "{})",
                               *a, *b, *inc));
        continue;
      }
      for (long id = *a; id <= *b; id += *inc) {
        if (!known.count(id)) {
          diag.error(k, d,
                     fmt::format("undefined {} {} (GENERATE {}, {}, {})", what, id, *a, *b, *inc));
          break;
        }
        ids.push_back(id);
      }
      continue;
    }
    for (size_t i = 0; i < d.fields.size(); ++i) {
      const std::string& f = d.fields[i];
      if (f.empty()) continue;
      if (std::isdigit(static_cast<unsigned char>(f[0])) || f[0] == '-' || f[0] == '+') {
        auto id = diag.integer(k, d, i);
        if (!id) continue;
        if (!known.count(*id)) {
          diag.error(k, d, fmt::format("undefined {} {}", what, *id));
          continue;
        }
        ids.push_back(*id);
      } else if (const Set* s = nodes ? mesh.nset(f) : mesh.elset(f)) {
        if (merged.insert(s).second) ids.insert(ids.end(), s->ids.begin(), s->ids.end());
      } else {
        diag.error(k, d, fmt::format("undefined {} set '{}'", what, f));
      }
    }
  }
  return ids;
}

void read_nodes(const Keyword& k, Mesh& mesh, Diagnostics& diag) {
  diag.check_options(k, {"NSET", "SYSTEM"});
  if (k.has("SYSTEM") && canonical(k.options.at("SYSTEM")) != "R")
    diag.error(k, "only SYSTEM=R (rectangular coordinates) is supported");
  std::vector<long> ids;
  bool normals = false;
  for (const auto& d : k.data) {
    if (d.fields.size() > 7) {
      diag.error(k, d,
                 "expected: node id, x, y, z (and optionally the normal's direction cosines)");
      continue;
    }
    // Fields 5-7: the direction cosines of a shell normal at the node (Abaqus, CalculiX), read
    // as numbers but not used: a membrane's normal is its surface's.
    for (size_t i = 4; i < d.fields.size(); ++i) diag.number(k, d, i, 0.0);
    if (d.fields.size() > 4 && !normals) {
      normals = true;
      diag.warn(k, d,
                "the normals given on the node lines (fields 5-7) are not read: a membrane's "
                "normal is that of its surface");
    }
    auto id = diag.integer(k, d, 0);
    auto x = diag.number(k, d, 1, 0.0), y = diag.number(k, d, 2, 0.0),
         z = diag.number(k, d, 3, 0.0);
    if (!id || !x || !y || !z) continue;
    if (*id <= 0) {
      diag.error(k, d, fmt::format("node ids are positive (got {})", *id));
      continue;
    }
    if (auto it = mesh.node_at.find(*id); it != mesh.node_at.end()) {
      diag.error(k, d, fmt::format("node {} is defined twice", *id));
      continue;
    }
    mesh.node_at[*id] = mesh.nodes.size();
    mesh.nodes.push_back({*id, Vec3(*x, *y, *z)});
    ids.push_back(*id);
  }
  if (k.has("NSET")) add_ids(set_named(mesh.nsets, mesh.nset_at, k.options.at("NSET"), k), ids);
}

void read_elements(const Keyword& k, Mesh& mesh, Diagnostics& diag) {
  diag.check_options(k, {"TYPE", "ELSET"});
  auto type_name = diag.required(k, "TYPE");
  if (!type_name) return;
  const std::string tn = canonical(*type_name);
  const shape::ShapeInfo* t = shape::find_abaqus(tn);
  if (!t) {
    diag.error(k, fmt::format("element type {} is not supported (membranes and trusses: {})", tn,
                              type_list()));
    return;
  }
  if (tn == t->abaqus_reduced)
    diag.warn(k, fmt::format("{}: Velum integrates a {} with its full Gauss rule (no reduced "
                             "integration with hourglass control)",
                             tn, t->name));
  std::vector<long> ids;
  // An element's nodes may continue on the next lines (Abaqus: a line ending in a comma;
  // CalculiX: until the element has its nodes).
  for (size_t i = 0; i < k.data.size(); ++i) {
    const DataLine& d = k.data[i];
    std::vector<std::string> fields = d.fields;
    while (static_cast<int>(fields.size()) < t->nodes + 1 && i + 1 < k.data.size()) {
      ++i;
      fields.insert(fields.end(), k.data[i].fields.begin(), k.data[i].fields.end());
    }
    const DataLine all{d.file, d.line, fields};
    if (static_cast<int>(fields.size()) != t->nodes + 1) {
      diag.error(k, d,
                 fmt::format("a {} needs an element id and {} node ids, got {} fields", tn,
                             t->nodes, fields.size()));
      continue;
    }
    auto id = diag.integer(k, all, 0);
    if (!id) continue;
    Element e{*id, std::string(t->name), {}, d.file, d.line};
    bool ok = true;
    for (int j = 1; j <= t->nodes && ok; ++j) {
      auto n = diag.integer(k, all, static_cast<size_t>(j));
      if (!n) {
        ok = false;
      } else if (!mesh.node_at.count(*n)) {
        diag.error(k, d, fmt::format("element {} refers to undefined node {}", *id, *n));
        ok = false;
      } else {
        e.nodes.push_back(*n);
      }
    }
    if (!ok) continue;
    if (*id <= 0) {
      diag.error(k, d, fmt::format("element ids are positive (got {})", *id));
      continue;
    }
    if (mesh.element_at.count(*id)) {
      diag.error(k, d, fmt::format("element {} is defined twice", *id));
      continue;
    }
    // Abaqus's node order to Velum's (Gmsh's): a T3D3 has its middle node second.
    std::array<long, shape::kMaxNodes> abaqus_nodes{};
    std::copy(e.nodes.begin(), e.nodes.end(), abaqus_nodes.begin());
    for (int j = 0; j < t->nodes; ++j)
      e.nodes[static_cast<size_t>(j)] =
          abaqus_nodes[static_cast<size_t>(t->from_abaqus[static_cast<size_t>(j)])];
    mesh.element_at[*id] = mesh.elements.size();
    mesh.elements.push_back(std::move(e));
    ids.push_back(*id);
  }
  if (k.has("ELSET"))
    add_ids(set_named(mesh.elsets, mesh.elset_at, k.options.at("ELSET"), k), ids);
  else
    mesh.unnamed_elements.insert(mesh.unnamed_elements.end(), ids.begin(), ids.end());
}

}  // namespace

const Set* Mesh::nset(const std::string& name) const {
  auto it = nset_at.find(canonical(name));
  return it == nset_at.end() ? nullptr : &nsets[it->second];
}
const Set* Mesh::elset(const std::string& name) const {
  auto it = elset_at.find(canonical(name));
  return it == elset_at.end() ? nullptr : &elsets[it->second];
}

Mesh read_mesh(const std::vector<Keyword>& keywords, std::vector<bool>& used, Diagnostics& diag) {
  Mesh mesh;
  for (size_t i = 0; i < keywords.size(); ++i) {
    const Keyword& k = keywords[i];
    if (k.name == "NODE") {
      read_nodes(k, mesh, diag);
    } else if (k.name == "ELEMENT") {
      read_elements(k, mesh, diag);
    } else if (k.name == "NSET" || k.name == "ELSET") {
      const bool nodes = k.name == "NSET";
      diag.check_options(
          k, nodes ? std::vector<std::string>{"NSET", "GENERATE", "ELSET", "UNSORTED", "INTERNAL"}
                   : std::vector<std::string>{"ELSET", "GENERATE", "UNSORTED", "INTERNAL"});
      auto name = diag.required(k, nodes ? "NSET" : "ELSET");
      if (!name) {
        used[i] = true;
        continue;
      }
      std::vector<long> ids;
      if (nodes && k.has("ELSET")) {  // the nodes of an element set
        if (!k.data.empty()) diag.error(k, "*NSET with ELSET= takes no data lines");
        if (const Set* es = mesh.elset(k.options.at("ELSET"))) {
          for (long e : es->ids)
            for (long n : mesh.elements[mesh.element_at.at(e)].nodes) ids.push_back(n);
        } else {
          diag.error(k, fmt::format("undefined element set '{}'", k.options.at("ELSET")));
        }
      } else {
        ids = set_members(k, nodes, mesh, diag);
      }
      Set& s = nodes ? set_named(mesh.nsets, mesh.nset_at, *name, k)
                     : set_named(mesh.elsets, mesh.elset_at, *name, k);
      add_ids(s, ids);
    } else {
      continue;
    }
    used[i] = true;
  }
  return mesh;
}

}  // namespace velum::io::inp
