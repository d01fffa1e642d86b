#include "velum/assembly/share_model.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "velum/assembly/dof_map.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {
namespace {

// The element graph (elements sharing a node are neighbours), elements numbered through the
// blocks in order: CSR offsets and ascending neighbour lists.
void element_graph(const Model& model, std::vector<long>& offsets, std::vector<long>& adjacency) {
  std::vector<long> first(model.blocks.size() + 1, 0);
  for (size_t b = 0; b < model.blocks.size(); ++b)
    first[b + 1] = first[b] + model.blocks[b]->size();
  std::vector<std::vector<long>> at_node(static_cast<size_t>(model.num_nodes()));
  for (size_t b = 0; b < model.blocks.size(); ++b)
    for (int e = 0; e < model.blocks[b]->size(); ++e)
      for (int n : model.blocks[b]->nodes(e))
        at_node[static_cast<size_t>(n)].push_back(first[b] + e);
  offsets.assign(1, 0);
  adjacency.clear();
  std::vector<long> near;
  for (size_t b = 0; b < model.blocks.size(); ++b)
    for (int e = 0; e < model.blocks[b]->size(); ++e) {
      near.clear();
      for (int n : model.blocks[b]->nodes(e))
        for (long other : at_node[static_cast<size_t>(n)])
          if (other != first[b] + e) near.push_back(other);
      std::sort(near.begin(), near.end());
      near.erase(std::unique(near.begin(), near.end()), near.end());
      adjacency.insert(adjacency.end(), near.begin(), near.end());
      offsets.push_back(static_cast<long>(adjacency.size()));
    }
}

// The piece's shared nodes and, per neighbouring process, those it holds too, from the
// (node, process) pairs of every node more than one process holds.
void share_nodes(ModelPiece& piece, std::vector<std::pair<int, int>>& also,
                 const std::vector<int>& local_of, int rank) {
  std::sort(also.begin(), also.end());
  also.erase(std::unique(also.begin(), also.end()), also.end());
  std::vector<int> at(piece.global_node.size(), -1);  // a local node's position in `shared`
  for (const auto& [n, p] : also)
    if (const int l = local_of[static_cast<size_t>(n)]; l >= 0 && at[static_cast<size_t>(l)] < 0) {
      at[static_cast<size_t>(l)] = static_cast<int>(piece.shared.size());
      piece.shared.push_back(l);
    }
  for (const auto& [n, p] : also)
    if (p != rank && local_of[static_cast<size_t>(n)] >= 0) piece.neighbours.push_back(p);
  std::sort(piece.neighbours.begin(), piece.neighbours.end());
  piece.neighbours.erase(std::unique(piece.neighbours.begin(), piece.neighbours.end()),
                         piece.neighbours.end());
  piece.shared_with.assign(piece.neighbours.size(), {});
  for (const auto& [n, p] : also)  // ascending node: each list in global order
    if (const int l = local_of[static_cast<size_t>(n)]; p != rank && l >= 0) {
      const auto q = std::lower_bound(piece.neighbours.begin(), piece.neighbours.end(), p) -
                     piece.neighbours.begin();
      piece.shared_with[static_cast<size_t>(q)].push_back(at[static_cast<size_t>(l)]);
    }
}

}  // namespace

void add_equation_owners(MeshSharing& sharing, const Model& whole) {
  if (processes::count() <= 1) return;
  add_equation_owners(sharing, whole, processes::count());
}

void add_equation_owners(MeshSharing& sharing, const Model& whole, int count) {
  if (whole.piece) throw std::logic_error("add_equation_owners: the model is already a piece");
  const DofMap dofs(whole);
  const std::vector<long> start = dofs.row_start(count);
  sharing.equation_owners.resize(static_cast<size_t>(whole.num_nodes()));
  for (int n = 0; n < whole.num_nodes(); ++n)
    for (int c = 0; c < 3; ++c)
      if (const long g = dofs.global_equation(n, c); g >= 0) {
        const int p =
            static_cast<int>(std::upper_bound(start.begin(), start.end(), g) - start.begin()) - 1;
        auto& owners = sharing.equation_owners[static_cast<size_t>(n)];
        if (std::find(owners.begin(), owners.end(), p) == owners.end()) owners.push_back(p);
      }
}

std::vector<int> row_rule_owners(const Model& model, const DofMap& whole, int count) {
  // An element belongs to the process that owns the row of its lowest equation (rows split in
  // contiguous even ranges): with a node numbering that follows the mesh (bandwidth-reduced,
  // or row by row), a process's elements form a band whose entries mostly fall in its own
  // rows. An element without equations goes round-robin.
  const long neq = whole.global_equations();
  std::vector<int> out;
  out.reserve(static_cast<size_t>(model.num_elements()));
  for (const auto& bp : model.blocks)
    for (int e = 0; e < bp->size(); ++e) {
      long lowest = neq;
      for (int n : bp->nodes(e))
        for (int c = 0; c < 3; ++c)
          if (const int q = whole.global_equation(n, c); q >= 0) lowest = std::min(lowest, long{q});
      out.push_back(lowest < neq ? processes::owner(lowest, neq, count) : e % count);
    }
  return out;
}

ModelPiece plan_piece(const Model& model, const DofMap& whole, int rank, int count,
                      const std::vector<int>& cell_owner,
                      const std::vector<std::vector<int>>* equation_owners,
                      std::vector<int>& local_of) {
  if (cell_owner.size() != static_cast<size_t>(model.num_elements()))
    throw std::logic_error("plan_piece: the element owners are for another mesh");
  const auto nn = static_cast<size_t>(model.num_nodes());
  ModelPiece piece;
  piece.global_nodes = model.num_nodes();
  if (model.num_nodes() > 0)
    piece.size = (model.X.rowwise().maxCoeff() - model.X.rowwise().minCoeff()).norm();
  const std::vector<long> start = whole.row_start(count);
  piece.global_equations = whole.global_equations();
  piece.whole_nodes = whole.whole_nodes();
  // Per node: the processes whose elements hold it (one, -1 none, -2 several) and the lowest
  // of them; the processes holding it at all (its elements', its equations' owners', the
  // first for nodes in no element and point masses' nodes); whether this process does.
  std::vector<int> element_holder(nn, -1), lowest(nn, 0), holder(nn, -1);
  std::vector<char> here(nn, 0);
  // (node, process) for every holder of a node more than one process holds (repeats sorted
  // out below): the shared nodes' neighbours.
  std::vector<std::pair<int, int>> also;
  auto hold = [&](size_t n, int p) {
    int& h = holder[n];
    if (h != -1 && h != p) {
      if (h >= 0) also.emplace_back(static_cast<int>(n), h);
      also.emplace_back(static_cast<int>(n), p);
      h = -2;
    } else {
      h = p;
    }
    if (p == rank) here[n] = 1;
  };
  size_t cell = 0;  // the element's index through the blocks
  for (const auto& bp : model.blocks) {
    auto& own = piece.own.emplace_back();
    for (int e = 0; e < bp->size(); ++e, ++cell) {
      const int p = cell_owner[cell];
      if (p == rank) own.push_back(e);
      for (int node : bp->nodes(e)) {
        const auto n = static_cast<size_t>(node);
        int& h = element_holder[n];
        lowest[n] = h == -1 ? p : std::min(lowest[n], p);
        h = (h == -1 || h == p) ? p : -2;
        hold(n, p);
      }
    }
  }
  // Every model's equations' owners hold the node, so that the pieces agree (a staged run).
  if (equation_owners)
    for (size_t n = 0; n < std::min(nn, equation_owners->size()); ++n)
      for (int p : (*equation_owners)[n]) hold(n, p);
  for (size_t n = 0; n < nn; ++n) {
    if (element_holder[n] == -1) hold(n, 0);
    for (int c = 0; c < 3; ++c)
      if (const long g = whole.global_equation(static_cast<int>(n), c); g >= 0)
        hold(n,
             static_cast<int>(std::upper_bound(start.begin(), start.end(), g) - start.begin()) - 1);
  }
  for (const auto& pm : model.masses) hold(static_cast<size_t>(pm.node), 0);

  // The piece's nodes, in global order.
  local_of.assign(nn, -1);
  for (size_t n = 0; n < nn; ++n)
    if (here[n]) {
      local_of[n] = static_cast<int>(piece.global_node.size());
      piece.global_node.push_back(static_cast<int>(n));
      for (int c = 0; c < 3; ++c)
        piece.equation.push_back(whole.global_equation(static_cast<int>(n), c));
      piece.kept.push_back(element_holder[n] == -1 ? rank == 0 : lowest[n] == rank);
    }
  for (size_t n = 0; n < nn; ++n)
    if (element_holder[n] == -2) ++piece.element_cut;
  share_nodes(piece, also, local_of, rank);
  // The first process also holds the diagonal blocks of the point masses' nodes (their mass
  // and the payload's drag Jacobian are added there once) and of nodes in no element, so
  // that the shares' patterns together are the one-process pattern.
  if (rank == 0) {
    for (size_t n = 0; n < nn; ++n)
      if (element_holder[n] == -1) piece.bare.push_back(local_of[n]);
    piece.lone = piece.bare;
    for (const auto& pm : model.masses)
      piece.lone.push_back(local_of[static_cast<size_t>(pm.node)]);
  }
  return piece;
}

namespace {

// share_model; `plan` null: this model alone.
std::vector<int> share(Model& model, ElementPartition partition, MeshSharing* plan) {
  const int count = processes::count();
  if (count <= 1) return {};
  if (model.piece) throw std::logic_error("share_model: the model is already a piece");
  const int rank = processes::rank();
  const DofMap whole(model);  // the global numbering, the same on every process

  // PT-Scotch on the element graph when asked for (a collective call); the row rule when it
  // is not, or not available.
  std::vector<int> graph_part;
  ElementPartition used = ElementPartition::kRows;
  std::string note;
  const bool planned = plan && !plan->cell_owner.empty();
  if (planned) {
    if (plan->cell_owner.size() != static_cast<size_t>(model.num_elements()))
      throw std::logic_error("share_model: the sharing is for another mesh");
    graph_part = plan->cell_owner;
    used = plan->partition;
    note = plan->partition_note;
  } else if (partition == ElementPartition::kScotch) {
    std::vector<long> offsets, adjacency;
    element_graph(model, offsets, adjacency);
    std::string why;
    if (processes::partition_graph(offsets, adjacency, graph_part, why))
      used = ElementPartition::kScotch;
    else
      note = why, graph_part.clear();
  }
  if (graph_part.empty()) graph_part = row_rule_owners(model, whole, count);
  if (plan && !planned) {  // the first model of the sharing: its elements' processes for all
    plan->partition = used;
    plan->partition_note = note;
    plan->cell_owner = graph_part;
  }
  std::vector<int> local_of;
  auto piece = std::make_shared<ModelPiece>(plan_piece(
      model, whole, rank, count, graph_part, plan ? &plan->equation_owners : nullptr, local_of));
  piece->partition = used;
  piece->partition_note = note;

  // The loads cut down to the piece while the mesh is whole (an edge load's boundary is the
  // whole mesh's); those with nothing here dropped.
  model.loads.keep_if([&](Load& load) { return load.keep_piece(model, piece->own, local_of); });

  // The model cut down to the piece.
  const auto nl = static_cast<Eigen::Index>(piece->global_node.size());
  NodePositions X(3, nl);
  NodePositions U0(3, model.U0.size() ? nl : 0);
  std::vector<long> ids(static_cast<size_t>(nl));
  for (Eigen::Index i = 0; i < nl; ++i) {
    const int g = piece->global_node[static_cast<size_t>(i)];
    X.col(i) = model.X.col(g);
    if (U0.size()) U0.col(i) = model.U0.col(g);
    ids[static_cast<size_t>(i)] = model.node_ids[static_cast<size_t>(g)];
  }
  model.X = std::move(X);
  model.U0 = std::move(U0);
  model.node_ids = std::move(ids);
  model.node_index.clear();
  for (size_t i = 0; i < model.node_ids.size(); ++i)
    model.node_index[model.node_ids[i]] = static_cast<int>(i);
  for (size_t b = 0; b < model.blocks.size(); ++b)
    model.blocks[b]->keep_piece(piece->own[b], local_of);
  std::vector<PointMass> masses;
  for (PointMass pm : model.masses)
    if (const int l = local_of[static_cast<size_t>(pm.node)]; l >= 0) {
      pm.node = l;
      masses.push_back(pm);
    }
  model.masses = std::move(masses);
  for (auto& f : model.fixed) restrict_nodes(f.nodes, local_of);
  for (auto& s : model.symmetry) restrict_nodes(s.nodes, local_of);
  for (auto& p : model.prescribed) restrict_nodes(p.nodes, local_of);
  model.piece = std::move(piece);
  return local_of;
}

}  // namespace

std::vector<int> share_model(Model& model, ElementPartition partition) {
  return share(model, partition, nullptr);
}

std::vector<int> share_model(Model& model, ElementPartition partition, MeshSharing& sharing) {
  return share(model, partition, &sharing);
}

}  // namespace velum
