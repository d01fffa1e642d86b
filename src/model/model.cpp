#include "velum/model/model.hpp"

#include <stdexcept>
#include <unordered_set>

#include "velum/shape/shape_info.hpp"

namespace velum {

int Model::add_node(long id, const Vec3& x) {
  if (node_index.count(id)) throw std::invalid_argument("duplicate node id " + std::to_string(id));
  const int i = num_nodes();
  X.conservativeResize(3, i + 1);
  X.col(i) = x;
  node_ids.push_back(id);
  node_index[id] = i;
  return i;
}

int Model::num_elements() const {
  int n = 0;
  for (const auto& b : blocks) n += b->size();
  return n;
}

namespace {
template <class Line>
void add_edge(const NodePositions& X, const std::vector<int>& nodes, const Vec3& t,
              NodePositions& F) {
  constexpr auto rule = Line::rule();
  typename Line::Values N, dN;
  for (int q = 0; q < Line::kPoints; ++q) {
    Line::eval(rule.xi[q][0], N, dN);
    Vec3 Xp = Vec3::Zero();
    for (int i = 0; i < Line::kNodes; ++i) Xp += dN[i] * X.col(nodes[i]);
    const double ds = Xp.norm() * rule.w[q];
    for (int i = 0; i < Line::kNodes; ++i) F.col(nodes[i]) += N[i] * ds * t;
  }
}
}  // namespace

std::vector<EdgeLoad::Edge> boundary_edges(const Model& model, const EdgeLoad& load) {
  const std::unordered_set<int> in_set(load.nodes.begin(), load.nodes.end());
  // Count every membrane edge by its sorted end nodes: boundary edges appear once.
  std::map<std::pair<int, int>, int> count;
  std::vector<std::pair<EdgeLoad::Edge, std::pair<int, int>>> candidates;  // with their key
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = model.blocks[bi];
    if (!b->surface()) continue;
    const shape::ShapeInfo& shape = b->shape();
    for (int e = 0; e < b->size(); ++e) {
      const auto nodes = b->nodes(e);
      for (int side = 0; side < shape.num_edges; ++side) {
        const auto ed = shape.edge(side);
        const int a = nodes[ed[0]], c = nodes[ed[1]];
        const std::pair<int, int> key{std::min(a, c), std::max(a, c)};
        ++count[key];
        bool all = true;
        for (int l : ed) all = all && in_set.count(nodes[l]);
        if (all) candidates.push_back({{static_cast<int>(bi), e, side}, key});
      }
    }
  }
  std::vector<EdgeLoad::Edge> out;
  for (const auto& [ed, key] : candidates)
    if (count[key] == 1) out.push_back(ed);
  return out;
}

NodePositions edge_load_forces(const Model& model, const EdgeLoad& load) {
  NodePositions F = NodePositions::Zero(3, model.num_nodes());
  const std::vector<EdgeLoad::Edge> found =
      load.resolved ? std::vector<EdgeLoad::Edge>{} : boundary_edges(model, load);
  for (const auto& ed : load.resolved ? load.edges : found) {
    const auto& b = model.blocks[static_cast<size_t>(ed.block)];
    const auto nodes = b->nodes(ed.element);
    std::vector<int> side;
    for (int l : b->shape().edge(ed.side)) side.push_back(nodes[l]);
    if (side.size() == 2)
      add_edge<shape::Line2>(model.X, side, load.force_per_length, F);
    else
      add_edge<shape::Line3>(model.X, side, load.force_per_length, F);
  }
  return F;
}

}  // namespace velum
