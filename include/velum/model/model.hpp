// The assembled description of a problem: nodes, element blocks, point masses, constraints,
// loads, time functions and damping. Built by io/ from a model file or directly through this
// API (tests, generators). Node and element indices are 0-based; the user's ids are kept for
// messages and output. Units are the user's, consistent, never converted.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "velum/model/element_block.hpp"
#include "velum/model/time_function.hpp"
#include "velum/parallel/model_piece.hpp"

namespace velum {

struct PointMass {
  int node = -1;
  double mass = 0;
  double drag_rho = 0, drag_cd_area = 0;  ///< f = −½ ρ C_D A |v| v, off when zero
};

/// Components x, y, z of a node held at zero displacement.
struct FixedDofs {
  std::vector<int> nodes;
  std::array<bool, 3> fix{false, false, false};
};

/// Nodes that stay on a plane through their reference position with unit normal `normal`.
struct SymmetryPlane {
  std::vector<int> nodes;
  Vec3 normal = Vec3::UnitZ();
};

/// u(t) = displacement · f(t) on every node of the set (all three components prescribed).
struct PrescribedMotion {
  std::vector<int> nodes;
  Vec3 displacement = Vec3::Zero();
  int function = -1;  ///< index into Model::functions, -1: constant 1
};

struct PointLoad {
  std::vector<int> nodes;
  Vec3 force = Vec3::Zero();  ///< on each node of the set
  int function = -1;
};

/// Force per reference length on the boundary edges of membranes whose nodes are all in the
/// set; converted to consistent nodal forces by Model::finalize.
struct EdgeLoad {
  std::vector<int> nodes;
  Vec3 force_per_length = Vec3::Zero();
  int function = -1;
  /// A membrane element's side (its `side`-th edge, in the shape's edge order).
  struct Edge {
    int block = -1, element = -1, side = -1;
  };
  /// The boundary edges loaded, once resolved on the whole mesh (share_model: a piece's own
  /// boundary cannot tell the cut between processes from the mesh's edge), restricted to the
  /// process's own elements. Not `resolved`: found from the mesh when the forces are made.
  std::vector<Edge> edges = {};
  bool resolved = false;
};

/// A pressure on membrane elements: a follower pressure along g1 x g2 per current area, or,
/// with `fixed_direction`, a load along the unit vector `direction` per area projected normal
/// to it (`projected`: snow per plan area) or per current area.
struct PressureLoad {
  int block = -1;
  std::vector<int> elements;  ///< indices into the block
  double value = 0;
  int function = -1;
  bool fixed_direction = false;
  Vec3 direction = Vec3::Zero();  ///< unit
  bool projected = true;
};

/// Gas enclosed by membrane elements together with the symmetry planes through `origin`
/// (docs/inflatables.md): absolute pressure p = initial_pressure (amount(t) V0 / V)^gamma,
/// the sheet loaded by p − ambient as a follower pressure. Set up (closure, orientation, V0)
/// by set_up_gas_chamber (model/gas_chamber.hpp).
struct GasLoad {
  struct Part {
    int block = -1;
    std::vector<int> elements;  ///< indices into the block
  };
  std::vector<Part> parts;
  double initial_pressure = 0, ambient = 0, gamma = 1;
  int amount = -1;  ///< time function of the gas amount (relative to the initial), -1: 1
  Vec3 origin = Vec3::Zero();
  double V0 = 0;  ///< reference volume, set by set_up_gas_chamber

  /// Absolute pressure at volume V and amount m; NaN when V <= 0 (a chamber turned inside
  /// out has no pressure: the residual turns non-finite and the step is cut).
  double pressure(double V, double m) const {
    return V > 0 ? initial_pressure * std::pow(m * V0 / V, gamma)
                 : std::numeric_limits<double>::quiet_NaN();
  }
};

struct GravityLoad {
  Vec3 acceleration = Vec3::Zero();
  int function = -1;
};

struct Model {
  // Nodes
  NodePositions X;                 ///< reference coordinates, 3 x nodes
  std::vector<long> node_ids;      ///< user ids, same order
  std::map<long, int> node_index;  ///< user id -> index

  std::vector<std::unique_ptr<ElementBlock>> blocks;
  std::vector<PointMass> masses;

  std::vector<FixedDofs> fixed;
  std::vector<SymmetryPlane> symmetry;
  std::vector<PrescribedMotion> prescribed;

  std::vector<PointLoad> point_loads;
  std::vector<EdgeLoad> edge_loads;
  std::vector<PressureLoad> pressures;
  std::vector<GasLoad> gases;
  std::vector<GravityLoad> gravity;
  std::vector<TimeFunction> functions;

  double rayleigh_mass = 0, rayleigh_stiffness = 0;

  /// Under mpirun, once shared out (share_model): which part of the whole model this is; its
  /// nodes are then the piece's, numbered locally. Null: the whole model (one process).
  std::shared_ptr<const ModelPiece> piece;

  int num_nodes() const { return static_cast<int>(X.cols()); }
  int add_node(long id, const Vec3& x);  ///< throws std::invalid_argument on a duplicate id
  double function_value(int f, double t) const { return f < 0 ? 1.0 : functions[f](t); }
  int num_elements() const;
};

/// The membrane sides all of whose nodes are in the load's set and that no other element
/// shares (the mesh's boundary), in the order of the blocks, elements and sides.
std::vector<EdgeLoad::Edge> boundary_edges(const Model& model, const EdgeLoad& load);
/// Nodal forces (3 x nodes) of an edge load at f(t) = 1: ∫ t H_N dS over its boundary edges
/// (on a piece of a shared model: over its own elements' edges only, this process's share).
NodePositions edge_load_forces(const Model& model, const EdgeLoad& load);

}  // namespace velum
