// Force per reference length on the boundary edges of membranes (load type `edge`), as
// consistent nodal forces, times its time function.
#pragma once

#include <memory>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

/// Force per reference length on the boundary edges of membranes whose nodes are all in the
/// set.
struct EdgeLoad {
  std::vector<int> nodes;
  Vec3 force_per_length = Vec3::Zero();
  int function = -1;
  /// A membrane element's side (its `side`-th edge, in the shape's edge order).
  struct Edge {
    int block = -1, element = -1, side = -1;
  };
  /// The boundary edges loaded, once resolved on the whole mesh (an MPI piece's own boundary
  /// cannot tell the cut between processes from the mesh's edge), restricted to the
  /// process's own elements. Not `resolved`: found from the mesh when the forces are made.
  std::vector<Edge> edges = {};
  bool resolved = false;
};

std::unique_ptr<Load> make_load(EdgeLoad p);

/// The membrane sides all of whose nodes are in the load's set and that no other element
/// shares (the mesh's boundary), in the order of the blocks, elements and sides.
std::vector<EdgeLoad::Edge> boundary_edges(const Model& model, const EdgeLoad& load);
/// Nodal forces (3 x nodes) of an edge load at f(t) = 1: ∫ t H_N dS over its boundary edges
/// (on a piece of a shared model: over its own elements' edges only, this process's share).
NodePositions edge_load_forces(const Model& model, const EdgeLoad& load);

}  // namespace velum
