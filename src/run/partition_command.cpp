// `velum partition`: the model read whole once, each process's piece computed by share_model's
// rules (assembly/share_model.hpp, plan_piece) and written as a part (io/mesh_part.hpp).
#include "velum/run/partition_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "run_parts.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/assembly/share_model.hpp"
#include "velum/io/mesh_part.hpp"
#include "velum/io/model_reader_yaml.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::run {
namespace {

constexpr int kMaxParts = 4096;

// What the split cannot carry yet (each needs the whole mesh at set-up, or data the parts do
// not hold): empty when the model can be split, else why, as "line: key: text".
std::string unsplittable(const ModelInput& in, const YAML::Node& root) {
  auto at = [](const YAML::Node& n, const std::string& key, const std::string& text) {
    return fmt::format("{}: {}: {}", n.Mark().line + 1, key, text);
  };
  const YAML::Node mesh = root["mesh"];
  if (mesh && mesh.IsMap())
    for (const char* key : {"positions", "reference_positions", "panel_references"})
      if (mesh[key])
        return at(mesh[key], fmt::format("mesh.{}", key), "not carried into parts yet");
  for (const char* key : {"rigid_bodies", "contact", "patterns"})
    if (root[key]) return at(root[key], key, "not read with mesh.parts yet");
  auto loads_of = [](const Model& m) -> std::string {
    static const std::set<std::string_view> kinds = {"point", "edge", "pressure", "gravity",
                                                     "drag"};
    for (const auto& load : m.loads)
      if (!kinds.count(load->kind())) return std::string(load->kind());
    return {};
  };
  std::vector<const Model*> models{&in.model};
  for (const auto& s : in.steps) models.push_back(&s.model);
  for (const Model* m : models) {
    if (const std::string k = loads_of(*m); !k.empty())
      return at(root["loads"] ? root["loads"] : root, "loads",
                fmt::format("a {} load is not read with mesh.parts yet", k));
    for (const auto& b : m->blocks)
      if (b->sliding())
        return at(root["sections"], "sections",
                  fmt::format("set '{}': sliding cables are not read with mesh.parts yet",
                              b->set_name()));
  }
  return {};
}

// The node ids sections name as sheet-axes points (their coordinates go to every part).
std::vector<std::pair<long, Vec3>> axes_points(const YAML::Node& root, const Model& m) {
  std::vector<std::pair<long, Vec3>> out;
  const YAML::Node ss = root["sections"];
  if (!ss || !ss.IsSequence()) return out;
  for (const auto& s : ss) {
    if (!s.IsMap() || !s["axes"] || !s["axes"].IsMap() || !s["axes"]["points"]) continue;
    for (const auto& p : s["axes"]["points"]) {
      long id = 0;
      if (!p.IsScalar() || !YAML::convert<long>::decode(p, id)) continue;
      if (auto it = m.node_index.find(id); it != m.node_index.end())
        out.emplace_back(id, m.X.col(it->second));
    }
  }
  return out;
}

}  // namespace

int partition_command(const std::filesystem::path& file, int parts,
                      const std::filesystem::path& dir) {
  if (processes::count() > 1) {
    say(stderr, "error: velum partition runs on one process (no mpirun)\n");
    return kExitBadInput;
  }
  if (parts < 2 || parts > kMaxParts) {
    say(stderr, "error: -n {}: give the number of processes to split for, 2 to {}\n", parts,
        kMaxParts);
    return kExitBadInput;
  }
  ModelInput in;
  YAML::Node root;
  try {
    root = load_model_yaml(file);
    in = read_model(file);
  } catch (const InputError& e) {
    for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
    say(stderr, "velum: {} error{} in {}: nothing written\n", e.messages().size(),
        e.messages().size() == 1 ? "" : "s", file.string());
    return kExitBadInput;
  }
  for (const auto& w : in.warnings) say(stderr, "warning: {}\n", w);
  if (const std::string why = unsplittable(in, root); !why.empty()) {
    say(stderr, "error: {}:{}: nothing written\n", file.string(), why);
    return kExitBadInput;
  }
  if (in.analysis.partition == ElementPartition::kScotch)
    say(stderr,
        "warning: {}: analysis.partition: scotch: the split shares the elements out by the "
        "row rule (PT-Scotch partitions at run time only)\n",
        file.string());

  // The models to number: the model, or each analysis step's (the same mesh).
  std::vector<const Model*> models;
  std::vector<PathSettings> paths;
  if (in.steps.empty()) {
    models.push_back(&in.model);
    paths.push_back(in.analysis.path);
  } else {
    for (const auto& s : in.steps) models.push_back(&s.model), paths.push_back(s.analysis.path);
  }
  const Model& whole = *models.front();
  std::vector<std::unique_ptr<DofMap>> dofs;
  MeshSharing sharing;
  try {
    for (size_t m = 0; m < models.size(); ++m) {
      dofs.push_back(std::make_unique<DofMap>(*models[m]));
      if (const std::string why = resolve_path_equation(paths[m], *models[m], *dofs.back());
          !why.empty()) {
        say(stderr, "error: {}: {}\n", file.string(), why);
        return kExitBadInput;
      }
      if (models.size() > 1) add_equation_owners(sharing, *models[m], parts);
    }
  } catch (const std::exception& e) {
    say(stderr, "error: {}: {}\n", file.string(), e.what());
    return kExitBadInput;
  }
  const std::vector<int> cell_owner = row_rule_owners(whole, *dofs.front(), parts);
  // Each element set's nodes (a node set by the set's name), and the edge loads' edges.
  std::map<std::string, std::vector<int>> set_nodes;
  for (const auto& b : whole.blocks) {
    auto& v = set_nodes[b->set_name()];
    for (int n : b->connectivity()) v.push_back(n);
  }
  for (auto& [name, v] : set_nodes) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  std::vector<std::vector<std::vector<EdgeLoad::Edge>>> edges(models.size());
  for (size_t m = 0; m < models.size(); ++m)
    for (const EdgeLoad& load : models[m]->edge_loads)
      edges[m].push_back(boundary_edges(*models[m], load));
  const auto points = axes_points(root, whole);

  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir, ec)) {
    say(stderr, "error: {}: cannot make the folder\n", dir.string());
    return kExitIo;
  }
  for (int r = parts;; ++r) {  // an earlier split's surplus parts
    const auto stale = mesh_part_file(dir, r);
    if (!std::filesystem::exists(stale, ec)) break;
    std::filesystem::remove(stale, ec);
  }
  size_t most_nodes = 0, most_elements = 0;
  for (int r = 0; r < parts; ++r) {
    io::MeshPart p;
    p.part = r;
    p.parts = parts;
    std::vector<int> local_of;
    const ModelPiece piece =
        plan_piece(whole, *dofs.front(), r, parts, cell_owner,
                   models.size() > 1 ? &sharing.equation_owners : nullptr, local_of);
    p.global_nodes = piece.global_nodes;
    p.size = piece.size;
    p.element_cut = piece.element_cut;
    p.global_node = piece.global_node;
    p.kept = piece.kept;
    p.lone = piece.lone;
    p.bare = piece.bare;
    p.shared = piece.shared;
    p.neighbours = piece.neighbours;
    p.shared_with = piece.shared_with;
    p.X.resize(3, static_cast<Eigen::Index>(piece.global_node.size()));
    for (size_t i = 0; i < piece.global_node.size(); ++i) {
      const int g = piece.global_node[i];
      p.node_id.push_back(whole.node_ids[static_cast<size_t>(g)]);
      p.X.col(static_cast<Eigen::Index>(i)) = whole.X.col(g);
    }
    for (size_t m = 0; m < models.size(); ++m) {
      io::MeshPart::Numbering& num = p.numberings.emplace_back();
      if (m == 0) {
        num.equation = piece.equation;
      } else {  // another step's numbering: the same nodes (the sharing holds them all)
        std::vector<int> lm;
        const ModelPiece other =
            plan_piece(*models[m], *dofs[m], r, parts, cell_owner, &sharing.equation_owners, lm);
        if (other.global_node != piece.global_node) {
          say(stderr,
              "error: {}: the steps' pieces differ (an internal error): nothing usable "
              "written\n",
              file.string());
          return kExitBadInput;
        }
        num.equation = other.equation;
      }
      num.global_equations = dofs[m]->global_equations();
      num.whole_nodes = dofs[m]->whole_nodes();
      num.path_equation =
          paths[m].method == PathSettings::Method::kDisplacement ? paths[m].equation : -1;
      for (const auto& all : edges[m]) {
        auto& mine = num.edge_loads.emplace_back();
        for (const auto& e : all)
          if (std::binary_search(piece.own[static_cast<size_t>(e.block)].begin(),
                                 piece.own[static_cast<size_t>(e.block)].end(), e.element))
            mine.push_back(e);
      }
    }
    size_t elements = 0;
    for (size_t b = 0; b < whole.blocks.size(); ++b) {
      const ElementBlock& blk = *whole.blocks[b];
      io::MeshPart::Group& g = p.groups.emplace_back();
      g.set = blk.set_name();
      g.type = std::string(blk.type_name());
      g.whole = blk.size();
      g.own = piece.own[b];
      elements += g.own.size();
      for (int e : g.own) {
        g.ids.push_back(in.element_ids[b][static_cast<size_t>(e)]);
        for (int n : blk.nodes(e)) g.node_ids.push_back(whole.node_ids[static_cast<size_t>(n)]);
      }
    }
    auto here = [&](const std::vector<int>& nodes) {
      std::vector<long> ids;
      for (int n : nodes)
        if (local_of[static_cast<size_t>(n)] >= 0)
          ids.push_back(whole.node_ids[static_cast<size_t>(n)]);
      return ids;
    };
    for (const auto& [name, nodes] : in.node_sets) p.node_sets[name] = here(nodes);
    for (const auto& [name, nodes] : set_nodes) p.element_set_nodes[name] = here(nodes);
    for (const HistoryEntry& h : in.output.history) p.history.push_back({h.block, h.element, h.xi});
    p.points = points;
    try {
      io::write_mesh_part(mesh_part_file(dir, r), p);
    } catch (const std::exception& e) {
      say(stderr, "error: {}\n", e.what());
      return kExitIo;
    }
    most_nodes = std::max(most_nodes, p.node_id.size());
    most_elements = std::max(most_elements, elements);
  }
  say(stdout,
      "velum partition: {} split into {} parts in {} (at most {} of {} nodes and {} of {} "
      "elements a part); run it with `mesh: {{parts: {}}}` on `mpirun -np {}`\n",
      file.string(), parts, dir.string(), most_nodes, whole.num_nodes(), most_elements,
      whole.num_elements(), dir.string(), parts);
  return kExitOk;
}

}  // namespace velum::run
