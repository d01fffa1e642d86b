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

#include "velum/load/drag_load.hpp"
#include "velum/load/edge_load.hpp"
#include "velum/load/gas_load.hpp"
#include "velum/load/gravity_load.hpp"
#include "velum/load/load_list.hpp"
#include "velum/load/point_load.hpp"
#include "velum/load/pressure_load.hpp"
#include "velum/model/element_block.hpp"
#include "velum/model/time_function.hpp"
#include "velum/parallel/model_piece.hpp"

namespace velum {

/// A point mass. Its payload's drag is a load (DragLoad, load/drag_load.hpp); the two drag
/// fields are kept so that initialisers of four values still compile, and must stay zero.
struct PointMass {
  int node = -1;
  double mass = 0;
  double drag_rho = 0, drag_cd_area = 0;
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

/// The velocity of the listed nodes at the start of a dynamic analysis (a free rigid body's).
struct InitialVelocity {
  std::vector<int> nodes;
  Vec3 velocity = Vec3::Zero();
};

/// The model's loads (load/load.hpp): one list, and views of it by kind for code that reads
/// or adds loads by their parameters. Copies and moves keep the views on their own list.
struct ModelLoads {
  LoadList loads;
  LoadsOf<PointLoad> point_loads{&loads};
  LoadsOf<EdgeLoad> edge_loads{&loads};
  LoadsOf<PressureLoad> pressures{&loads};  ///< follower and directed
  LoadsOf<GasLoad> gases{&loads};
  LoadsOf<GravityLoad> gravity{&loads};
  LoadsOf<DragLoad> drag{&loads};

  ModelLoads() = default;
  ModelLoads(const ModelLoads& o) : loads(o.loads) {}
  ModelLoads(ModelLoads&& o) noexcept : loads(std::move(o.loads)) {}
  ModelLoads& operator=(const ModelLoads& o) {
    loads = o.loads;
    return *this;
  }
  ModelLoads& operator=(ModelLoads&& o) noexcept {
    loads = std::move(o.loads);
    return *this;
  }
  ~ModelLoads() = default;
};

struct Model : ModelLoads {
  // Nodes
  NodePositions X;                 ///< reference coordinates, 3 x nodes
  std::vector<long> node_ids;      ///< user ids, same order
  std::map<long, int> node_index;  ///< user id -> index
  /// Where the sheet starts, as a displacement from its stress-free reference X (the start
  /// coordinates minus mesh.reference_positions): 3 x nodes, or empty when it starts at X.
  /// Fixed and symmetry components hold it, prescribed motions are added to it.
  NodePositions U0;

  std::vector<std::unique_ptr<ElementBlock>> blocks;
  std::vector<PointMass> masses;

  std::vector<FixedDofs> fixed;
  std::vector<SymmetryPlane> symmetry;
  std::vector<PrescribedMotion> prescribed;
  std::vector<InitialVelocity> initial_velocities;

  std::vector<TimeFunction> functions;

  double rayleigh_mass = 0, rayleigh_stiffness = 0;

  /// Under mpirun, once shared out (share_model): which part of the whole model this is; its
  /// nodes are then the piece's, numbered locally. Null: the whole model (one process).
  std::shared_ptr<const ModelPiece> piece;

  int num_nodes() const { return static_cast<int>(X.cols()); }
  /// The start displacement of node n (zero without reference positions).
  Vec3 start_displacement(int n) const { return U0.size() ? Vec3(U0.col(n)) : Vec3::Zero(); }
  int add_node(long id, const Vec3& x);  ///< throws std::invalid_argument on a duplicate id
  double function_value(int f, double t) const { return f < 0 ? 1.0 : functions[f](t); }
  int num_elements() const;
};

}  // namespace velum
