// Force per reference length on the boundary edges of membranes: the edges found on the whole
// mesh (before an MPI cut), their consistent nodal forces made once.
#include "velum/load/edge_load.hpp"

#include <map>
#include <stdexcept>
#include <unordered_set>

#include "nodal_vector.hpp"
#include "velum/model/model.hpp"
#include "velum/shape/shape_info.hpp"
#include "velum/shape/shapes.hpp"

namespace velum {
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

namespace {

class EdgeForce final : public Load, public EdgeLoad {
 public:
  explicit EdgeForce(EdgeLoad p) : EdgeLoad(std::move(p)) {}
  std::string_view kind() const override { return "edge"; }
  LoadOrder order() const override { return LoadOrder::kEdge; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<EdgeForce>(*this); }
  void set_up(const Model& model, const ElementNamer&) override {
    // On an MPI piece its edges were found on the whole mesh when it was cut (and checked
    // there): the piece may hold none of them.
    if (resolved) return;
    const NodePositions F = edge_load_forces(model, *this);
    if (F.cwiseAbs().maxCoeff() == 0 && force_per_length.norm() > 0)
      throw std::invalid_argument("no membrane boundary edge has all its nodes in this node set");
  }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    auto h = std::make_unique<EdgeForce>(*this);
    h->force_per_length = force_per_length * owner.function_value(function, t);
    h->function = -1;
    return h;
  }
  bool keep_piece(const Model& whole, const std::vector<std::vector<int>>& own,
                  const std::vector<int>& local_of) override {
    // The mesh's boundary, found while the mesh is whole: this process's share.
    edges.clear();
    for (const auto& ed : boundary_edges(whole, *this))
      if (std::binary_search(own[static_cast<size_t>(ed.block)].begin(),
                             own[static_cast<size_t>(ed.block)].end(), ed.element))
        edges.push_back(ed);
    resolved = true;
    restrict_nodes(nodes, local_of);
    return true;
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class EdgeForceTerm final : public LoadTerm {
 public:
  EdgeForceTerm(const EdgeForce& load, const LoadSite& site)
      : load_(load), site_(site), F_(edge_load_forces(site.model, load)) {
    // On a piece: its own elements' edges, completed where processes share nodes.
    site.assembler.sum_at_shared_nodes(F_);
  }
  void add(const LoadState& s, LoadOutput& out) override {
    add_nodal_vector(site_.assembler, site_.model.function_value(load_.function, s.t), F_, out.F);
  }

 private:
  const EdgeForce& load_;
  LoadSite site_;
  NodePositions F_;  ///< at f(t) = 1
};

std::unique_ptr<LoadTerm> EdgeForce::bind(const LoadSite& site) const {
  return std::make_unique<EdgeForceTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(EdgeLoad p) {
  return std::make_unique<EdgeForce>(std::move(p));
}

}  // namespace velum
