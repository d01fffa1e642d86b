// Reads mesh.parts: a model split by `velum partition` into one part per MPI process
// (docs/parallel.md "Reading the mesh in parts"). Each process reads its own part only: the
// nodes it holds (in the whole model's order, so its local numbering is the piece's), its own
// elements in their groups, and the node sets cut to it; the blocks are spread to the whole
// blocks' numbering as they are built (build_blocks), and the piece is made from the part
// once the model is read (finish_part). No process holds the whole mesh; share_model is not
// called on such a model (Model::piece is set already).

#include <fmt/format.h>

#include <fstream>

#include "reader.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io::model_file {
namespace {

/// Reads the "part K P" header of a part file: P, or 0 when it has none.
int parts_in(const std::filesystem::path& file) {
  std::ifstream f(file);
  std::string magic, key;
  int version = 0, k = 0, p = 0;
  if (f >> magic >> version >> key >> k >> p && magic == "velum-part" && key == "part") return p;
  return 0;
}

}  // namespace

void Reader::parse_parts(const Node& mesh) {
  mesh_ok_ = false;
  parts_given_ = true;
  if (!check_map(mesh, "mesh", {"parts"})) {
    error(mesh, "mesh",
          "mesh.parts holds the whole mesh (nodes, elements and node sets, written by `velum "
          "partition`): give it alone");
    return;
  }
  const auto dir_name = text(mesh, "parts", "mesh", true);
  if (!dir_name) return;
  std::filesystem::path dir = *dir_name;
  if (dir.is_relative()) dir = base_dir_ / dir;
  const Node at = mesh["parts"];
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    error(at, "mesh.parts",
          fmt::format("{}: no such folder (write the parts with `velum partition MODEL -n P -o "
                      "DIR`)",
                      dir.string()));
    return;
  }
  const int rank = processes::rank(), count = processes::count();
  const std::filesystem::path first = mesh_part_file(dir, 0);
  const int parts = parts_in(first);
  if (parts <= 0) {
    error(at, "mesh.parts",
          fmt::format("{}: missing or not a part of `velum partition` (the folder holds no split "
                      "model)",
                      first.string()));
    return;
  }
  if (parts != count && count == 1) {
    error(at, "mesh.parts",
          fmt::format("{} holds the model split into {} parts ({}): a model read in parts runs "
                      "under mpirun, one process a part: `mpirun -np {} velum run ...`",
                      dir.string(), parts, first.string(), parts));
    return;
  }
  if (parts != count) {
    error(at, "mesh.parts",
          fmt::format("{} holds the model split into {} parts ({}), but this run has {} "
                      "process{}: run it with `mpirun -np {}`, or split it again with `velum "
                      "partition -n {}`",
                      dir.string(), parts, first.string(), count, count == 1 ? "" : "es", parts,
                      count));
    return;
  }
  try {
    part_ = std::make_unique<MeshPart>(read_mesh_part(mesh_part_file(dir, rank)));
  } catch (const std::exception& e) {
    error(at, "mesh.parts", e.what());
    return;
  }
  MeshPart& p = *part_;
  if (p.part != rank || p.parts != count) {
    error(at, "mesh.parts",
          fmt::format("{}: part {} of {}, read by process {} of {}: the folder mixes splits; "
                      "split the model again",
                      mesh_part_file(dir, rank).string(), p.part, p.parts, rank, count));
    part_.reset();
    return;
  }
  if (step_ >= p.numberings.size()) {
    error(at, "mesh.parts",
          fmt::format("the model has more analysis steps than the split ({}): split the model "
                      "again with `velum partition`",
                      p.numberings.size()));
    part_.reset();
    return;
  }
  // The nodes, in the whole model's order: their local numbering is the piece's.
  for (size_t i = 0; i < p.node_id.size(); ++i)
    add_node(p.node_id[i], p.X.col(static_cast<Eigen::Index>(i)), at, "mesh.parts");
  for (MeshPart::Group& g : p.groups) {
    const shape::ShapeInfo* s = shape::find(g.type);
    if (!s && g.type != "sliding_cable") {
      error(at, "mesh.parts", fmt::format("a group of unknown element type '{}'", g.type));
      return;
    }
    ElementSet& set = element_sets_[g.set];
    set.from_file = true;
    set.dimension = s && s->surface() ? 2 : 1;
    set.groups.push_back(ElementGroup{g.set, g.type, std::move(g.ids), std::move(g.node_ids), 0});
    part_groups_[g.set].emplace_back(g.whole, std::move(g.own));
  }
  p.groups.clear();
  auto local = [&](const std::vector<long>& ids) {
    std::vector<int> out;
    out.reserve(ids.size());
    for (long id : ids)
      if (auto it = in_.model.node_index.find(id); it != in_.model.node_index.end())
        out.push_back(it->second);
    return out;
  };
  for (const auto& [name, ids] : p.node_sets) node_sets_[name] = local(ids);
  for (const auto& [name, ids] : p.element_set_nodes) part_set_nodes_[name] = local(ids);
  p.node_sets.clear();
  p.element_set_nodes.clear();
  in_.node_sets = node_sets_;
  mesh_ok_ = errors_.empty();
}

void Reader::finish_part() {
  MeshPart& p = *part_;
  const MeshPart::Numbering& num = p.numberings[step_];
  if (part_own_.size() != in_.model.blocks.size()) {
    errors_.push_back(
        fmt::format("{}: mesh.parts: the sections build other blocks than the "
                    "split's: split the model again with `velum partition`",
                    name_));
    return;
  }
  auto piece = std::make_shared<ModelPiece>();
  piece->global_nodes = p.global_nodes;
  piece->global_node = p.global_node;
  piece->equation = num.equation;
  piece->global_equations = num.global_equations;
  piece->whole_nodes = num.whole_nodes;
  piece->size = p.size;
  piece->own = std::move(part_own_);
  piece->kept = p.kept;
  piece->lone = p.lone;
  piece->bare = p.bare;
  piece->shared = p.shared;
  piece->neighbours = p.neighbours;
  piece->shared_with = p.shared_with;
  piece->element_cut = p.element_cut;
  // The edge loads' edges, found on the whole mesh by the split.
  if (in_.model.edge_loads.size() != num.edge_loads.size()) {
    errors_.push_back(
        fmt::format("{}: mesh.parts: the model's edge loads are not the split's: "
                    "split the model again with `velum partition`",
                    name_));
    return;
  }
  for (size_t k = 0; k < num.edge_loads.size(); ++k) {
    in_.model.edge_loads[k].edges = num.edge_loads[k];
    in_.model.edge_loads[k].resolved = true;
  }
  // Nodes in no element (the first part holds them): fixed, as a whole read fixes them.
  if (!p.bare.empty()) {
    FixedDofs f;
    f.fix = {true, true, true};
    f.nodes = p.bare;
    in_.model.fixed.push_back(std::move(f));
  }
  if (PathSettings& path = in_.analysis.path; path.method == PathSettings::Method::kDisplacement)
    path.equation = num.path_equation;
  in_.model.piece = std::move(piece);
}

bool Reader::place_from_part(HistoryEntry& he, size_t index) const {
  if (index >= part_->history.size() || part_->history[index].block < 0) return false;
  const MeshPart::Place& at = part_->history[index];
  he.block = at.block;
  he.element = at.element;
  he.xi = at.xi;
  return true;
}

}  // namespace velum::io::model_file
