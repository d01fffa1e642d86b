#include "velum/model/gas_chamber.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include "velum/element/enclosed_volume.hpp"

namespace velum {
namespace {

struct EdgeUse {
  int part = 0, element = 0;
  bool forward = true;     ///< traversed from the smaller corner index to the larger
  std::vector<int> nodes;  ///< model node indices
  int count = 0;
  int other_part = 0, other_element = 0;  ///< the second element along it
};

/// Union-find over the chamber's elements (numbered part by part), for its connected pieces.
struct Pieces {
  std::vector<int> up;
  int find(int i) {
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
  }
  void join(int a, int b) { up[find(a)] = find(b); }
};

}  // namespace

double gas_chamber_volume(const Model& model, const GasLoad& gas, const NodePositions& x) {
  double V = 0;
  for (const auto& part : gas.parts) {
    const auto& b = *model.blocks[part.block];
    const auto kernel = make_surface_volume_kernel(b.type_name());
    V += kernel->volume(part.elements, b.connectivity(), x, gas.origin);
  }
  return V;
}

void set_up_gas_chamber(const Model& model, GasLoad& gas,
                        const std::function<long(int, int)>& element_id) {
  auto element_name = [&](int part, int e) {
    const int b = gas.parts[part].block;
    return element_id ? element_id(b, e) : static_cast<long>(e) + 1;
  };
  if (gas.parts.empty()) throw std::invalid_argument("the gas chamber lists no elements");
  // The chamber is measured where the sheet starts (the reference coordinates plus the start
  // displacement of mesh.reference_positions), as an airbag's initial volume is its folded
  // one: a bag sewn from two flat panels encloses nothing at its reference. The reference
  // coordinates only give the stress-free metric; symmetry holds the start position.
  NodePositions start;
  if (model.U0.size()) start = model.X + model.U0;
  const NodePositions& x0 = model.U0.size() ? start : model.X;
  // Extent of the chamber, for the tolerance of "on the plane".
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& part : gas.parts) {
    const auto& b = *model.blocks[part.block];
    if (!make_surface_volume_kernel(b.type_name()))
      throw std::invalid_argument(
          fmt::format("gas acts on membranes; set '{}' holds {}", b.set_name(), b.type_name()));
    for (int e : part.elements)
      for (int n : b.nodes(e)) lo = lo.cwiseMin(x0.col(n)), hi = hi.cwiseMax(x0.col(n));
  }
  const double tol = 1e-8 * (hi - lo).norm();
  auto id = [&](int n) { return model.node_ids[n]; };

  // Edges keyed by their corner nodes (sorted).
  std::map<std::pair<int, int>, EdgeUse> edges;
  for (size_t pi = 0; pi < gas.parts.size(); ++pi) {
    const auto& b = *model.blocks[gas.parts[pi].block];
    const shape::ShapeInfo& shape = b.shape();  // edges in the element's direction of traversal
    for (int e : gas.parts[pi].elements) {
      const auto nodes = b.nodes(e);
      for (int side = 0; side < shape.num_edges; ++side) {
        const auto le = shape.edge(side);
        const int a = nodes[le[0]], c = nodes[le[1]];
        auto& use = edges[{std::min(a, c), std::max(a, c)}];
        const bool forward = a < c;
        if (use.count == 1 && use.forward == forward) {
          const auto& other = *model.blocks[gas.parts[use.part].block];
          throw std::invalid_argument(fmt::format(
              "elements {} of set '{}' and {} of set '{}' run the same way along the edge from "
              "node {} to node {}: their normals g1 x g2 point to opposite sides; orient every "
              "element of the chamber so that g1 x g2 points out of the gas",
              element_name(use.part, use.element), other.set_name(),
              element_name(static_cast<int>(pi), e), b.set_name(), id(a), id(c)));
        }
        if (use.count == 2)
          throw std::invalid_argument(fmt::format(
              "the edge from node {} to node {} is shared by three or more elements of the "
              "chamber: a chamber's surface must be a closed sheet (one gas load per chamber)",
              id(a), id(c)));
        // Quadratic edges (corners, then the mid-side node): the same corners but another
        // mid-side node leave a slit.
        if (use.count == 1 && le.size() > 2 && use.nodes[2] != nodes[le[2]]) {
          const auto& other = *model.blocks[gas.parts[use.part].block];
          throw std::invalid_argument(fmt::format(
              "elements {} of set '{}' and {} of set '{}' share the corners of the edge from "
              "node {} to node {} but not its mid-side node ({} and {}): the surface has a slit "
              "there; give both elements the same mid-side node",
              element_name(use.part, use.element), other.set_name(),
              element_name(static_cast<int>(pi), e), b.set_name(), id(a), id(c), id(use.nodes[2]),
              id(nodes[le[2]])));
        }
        if (use.count == 0) {
          use.part = static_cast<int>(pi), use.element = e, use.forward = forward;
          for (int k : le) use.nodes.push_back(nodes[k]);
        } else {
          use.other_part = static_cast<int>(pi), use.other_element = e;
        }
        ++use.count;
      }
    }
  }

  // Normals of the planes each node is held on (symmetry, or fixed components).
  std::vector<std::vector<Vec3>> held(model.num_nodes());
  for (const auto& s : model.symmetry)
    for (int n : s.nodes) held[n].push_back(s.normal);
  for (const auto& f : model.fixed)
    for (int c = 0; c < 3; ++c)
      if (f.fix[c])
        for (int n : f.nodes) held[n].push_back(Vec3::Unit(c));
  auto on_plane = [&](int n, const Vec3& normal) {
    if (std::abs((x0.col(n) - gas.origin).dot(normal)) > tol) return false;
    return std::any_of(held[n].begin(), held[n].end(),
                       [&](const Vec3& h) { return std::abs(std::abs(h.dot(normal)) - 1) < 1e-9; });
  };
  std::vector<Vec3> planes;  // orthonormal directions across the planes that close the chamber
  for (const auto& [key, use] : edges) {
    if (use.count == 2) continue;
    bool closed = false;
    for (const Vec3& normal : held[use.nodes[0]])
      if (std::all_of(use.nodes.begin(), use.nodes.end(),
                      [&](int n) { return on_plane(n, normal); })) {
        closed = true;
        Vec3 q = normal;
        for (const Vec3& p : planes) q -= q.dot(p) * p;
        if (q.norm() > 1e-6) planes.push_back(q.normalized());
        break;
      }
    if (!closed) {
      const auto& b = *model.blocks[gas.parts[use.part].block];
      throw std::invalid_argument(fmt::format(
          "the surface is not closed: the edge from node {} to node {} (element {} of set '{}') "
          "belongs to one element only and lies on no symmetry plane through the origin [{}, "
          "{}, {}] (a plane whose nodes a symmetry or fix boundary condition holds on it); "
          "close the surface, add the symmetry condition, or move `origin` onto the planes",
          id(key.first), id(key.second), element_name(use.part, use.element), b.set_name(),
          gas.origin.x(), gas.origin.y(), gas.origin.z()));
    }
  }

  // The volume (1/3) ∫ (x - o)·n dA sums terms of the size |x - o| |dA| that cancel down to V:
  // an origin far from the chamber (a model placed 1e4 from its own origin) loses as many
  // digits in V, the gas forces and their tangent, and Newton its convergence. Move it next to
  // the chamber, along the planes that close it (V does not change); an origin near the
  // chamber is kept as given.
  Vec3 towards = 0.5 * (lo + hi) - gas.origin;
  for (const Vec3& p : planes) towards -= towards.dot(p) * p;
  if (towards.norm() > (hi - lo).norm()) gas.origin += towards;

  // Each connected piece of the surface encloses gas of its own sign: a piece turned inside
  // out beside a larger one the right way round would leave the total positive.
  std::vector<int> first(gas.parts.size() + 1, 0);
  for (size_t pi = 0; pi < gas.parts.size(); ++pi)
    first[pi + 1] = first[pi] + static_cast<int>(gas.parts[pi].elements.size());
  std::vector<std::vector<int>> slot(gas.parts.size());  // element index -> its place in part
  for (size_t pi = 0; pi < gas.parts.size(); ++pi) {
    slot[pi].assign(static_cast<size_t>(model.blocks[gas.parts[pi].block]->size()), -1);
    for (size_t k = 0; k < gas.parts[pi].elements.size(); ++k)
      slot[pi][static_cast<size_t>(gas.parts[pi].elements[k])] = static_cast<int>(k);
  }
  auto global = [&](int part, int e) { return first[part] + slot[part][e]; };
  Pieces pieces{std::vector<int>(static_cast<size_t>(first.back()))};
  for (size_t i = 0; i < pieces.up.size(); ++i) pieces.up[i] = static_cast<int>(i);
  for (const auto& [key, use] : edges)
    if (use.count == 2)
      pieces.join(global(use.part, use.element), global(use.other_part, use.other_element));
  struct Piece {
    GasLoad chamber;            ///< the piece as a chamber of its own, for its volume
    int part = 0, element = 0;  ///< its first element, for the message
  };
  std::map<int, Piece> by_piece;
  for (size_t pi = 0; pi < gas.parts.size(); ++pi)
    for (int e : gas.parts[pi].elements) {
      auto [it, fresh] = by_piece.try_emplace(pieces.find(global(static_cast<int>(pi), e)));
      Piece& piece = it->second;
      if (fresh) piece.part = static_cast<int>(pi), piece.element = e;
      auto& parts = piece.chamber.parts;
      if (parts.empty() || parts.back().block != gas.parts[pi].block)
        parts.push_back({gas.parts[pi].block, {}});
      parts.back().elements.push_back(e);
    }
  if (by_piece.size() > 1)
    for (auto& [root, piece] : by_piece) {
      piece.chamber.origin = gas.origin;
      const double v = gas_chamber_volume(model, piece.chamber, x0);
      if (!(v > 0))
        throw std::invalid_argument(fmt::format(
            "the surface has {} separate pieces and the one with element {} of set '{}' "
            "encloses a volume of {:.6g}, not positive: its normals g1 x g2 point into the gas; "
            "reverse the node order of its elements (the normals must point out of the gas)",
            by_piece.size(), element_name(piece.part, piece.element),
            model.blocks[gas.parts[piece.part].block]->set_name(), v));
    }

  const double V = gas_chamber_volume(model, gas, x0);
  // Zero to round-off (the cone volumes of the elements, each at most the chamber's extent
  // times its area, sum to it): a sheet lying in a plane through the origin, or one that
  // encloses nothing with the planes. A thin chamber (a tube of 1 mm over 100 m) stays far
  // above it.
  double area = 0;
  for (const auto& part : gas.parts)
    for (int e : part.elements) area += model.blocks[part.block]->measure(e);
  if (std::abs(V) <= 1e-12 * (hi - lo).norm() * area)
    throw std::invalid_argument(fmt::format(
        "the enclosed volume is {:.3g}, zero to round-off: the chamber is flat or degenerate "
        "(its sheet encloses no gas with the symmetry planes through the origin [{}, {}, {}]); "
        "give it a start shape that encloses gas (a bulge, e.g. the sheet lifted off its "
        "symmetry plane in the middle) or check the symmetry planes and `origin`",
        V, gas.origin.x(), gas.origin.y(), gas.origin.z()));
  if (!(V > 0))
    throw std::invalid_argument(fmt::format(
        "the enclosed volume is {:.6g}, not positive: the normals g1 x g2 of the elements point "
        "into the gas; reverse the node order of the elements (the normals must point out of "
        "the gas)",
        V));
  gas.V0 = V;
}

}  // namespace velum
