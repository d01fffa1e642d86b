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
  // Extent of the chamber, for the tolerance of "on the plane".
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& part : gas.parts) {
    const auto& b = *model.blocks[part.block];
    if (!make_surface_volume_kernel(b.type_name()))
      throw std::invalid_argument(
          fmt::format("gas acts on membranes; set '{}' holds {}", b.set_name(), b.type_name()));
    for (int e : part.elements)
      for (int n : b.nodes(e)) lo = lo.cwiseMin(model.X.col(n)), hi = hi.cwiseMax(model.X.col(n));
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
        if (use.count == 0) {
          use.part = static_cast<int>(pi), use.element = e, use.forward = forward;
          for (int k : le) use.nodes.push_back(nodes[k]);
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
    if (std::abs((model.X.col(n) - gas.origin).dot(normal)) > tol) return false;
    return std::any_of(held[n].begin(), held[n].end(),
                       [&](const Vec3& h) { return std::abs(std::abs(h.dot(normal)) - 1) < 1e-9; });
  };
  for (const auto& [key, use] : edges) {
    if (use.count == 2) continue;
    bool closed = false;
    for (const Vec3& normal : held[use.nodes[0]])
      if (std::all_of(use.nodes.begin(), use.nodes.end(),
                      [&](int n) { return on_plane(n, normal); })) {
        closed = true;
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

  const double V = gas_chamber_volume(model, gas, model.X);
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
