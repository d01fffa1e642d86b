// A load as an object: what the model holds (its parameters, its set-up on the mesh, what it
// becomes when a step holds it, its share of a model cut into MPI pieces, its summary) and,
// bound to an assembler, the term that adds its forces, load stiffness and low-rank Jacobian
// part at a state. Units the model's; forces in the global frame, per node (3 x nodes).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "velum/math/sparse.hpp"
#include "velum/math/types.hpp"

namespace velum {

// A load is set up on a model and bound to the model's assembler: the load headers name them
// only (they sit above the loads, which the model holds).
struct Model;
class Assembler;
class DofMap;
struct LowRankJacobian;
/// Per-node vectors, 3 x nodes (as in model/element_block.hpp).
using NodePositions = Eigen::Matrix<double, 3, Eigen::Dynamic>;

/// Where a load's forces enter the sum of the external forces. Loads are kept in this order
/// (and in the order given within one), so that the sum is made in one fixed order.
enum class LoadOrder : int { kNodal = 0, kEdge, kBody, kSurface, kChamber, kVelocity, kContact };

/// What a bound load reaches: the model (its current piece on several processes), the
/// assembler over its elements and the equations.
struct LoadSite {
  const Model& model;
  const Assembler& assembler;
  const DofMap& dofs;
};

/// The state a load is evaluated at.
struct LoadState {
  double t = 0;
  const NodePositions& x;  ///< current positions
  const NodePositions& V;  ///< node velocities (filled when some load uses_velocity())
  /// The follower pressures on whole blocks came through the blocks' internal pass
  /// (whole_block_pressure): their forces are already summed.
  bool fused = false;
  /// The forces the supports carry (the output's reactions) rather than the residual's: they
  /// differ for a load derived from a potential that the supports close (the gas: (p − p_a)
  /// ∂V/∂x, whose volume closed by the symmetry planes adds a part normal to the planes at
  /// their nodes; the supports carry the traction p − p_a on the sheet).
  bool at_supports = false;
};

/// Where a bound load adds: the external forces F (3 x nodes), the load stiffness subtracted
/// from K (r = f_int − f_ext: K − ∂f/∂x) when K != null, and its low-rank columns from
/// `column` on (when K != null: the Jacobian's dense part U Wᵀ, see low_rank_columns()).
struct LoadOutput {
  NodePositions& F;
  SparseMatrix* K = nullptr;
  LowRankJacobian* low_rank = nullptr;
  int column = 0;
};

/// A load bound to one assembler: evaluated at every residual.
class LoadTerm {
 public:
  virtual ~LoadTerm() = default;
  /// Adds the forces at `s` (and, see LoadOutput, the load stiffness and low-rank part).
  virtual void add(const LoadState& s, LoadOutput& out) = 0;
  /// Columns of the Jacobian's low-rank part this load writes (the gas: one, a chamber).
  virtual int low_rank_columns() const { return 0; }
  /// Couplings beyond the mesh's elements (a contact's node with the nodes of the face it
  /// touches), which add() writes into K as 3 x 3 node blocks: the system asks before it
  /// assembles a Jacobian, at the positions add() is then called with (once, right before),
  /// and rebuilds the Jacobian's pattern (Assembler::set_couplings) when a load says they
  /// changed. Returns true when the node pairs couplings() lists changed since the last call.
  virtual bool update_couplings(const NodePositions& /*x*/) { return false; }
  /// Those node pairs (model nodes, each pair once, either order), appended to `pairs`.
  virtual void couplings(std::vector<std::array<int, 2>>& /*pairs*/) const {}
  /// A follower pressure on every element of a block: its block and its pressure at t, to go
  /// through the block's internal pass (one scatter of K − Kp); false otherwise.
  virtual bool whole_block_pressure(double /*t*/, int& /*block*/, double& /*p*/) const {
    return false;
  }
  /// Forces depend on the velocity: the caller fills LoadState::V.
  virtual bool uses_velocity() const { return false; }
  /// Adds cv ∂(−f)/∂v to J (a velocity-dependent load; the first process only on several).
  virtual void add_velocity_jacobian(const NodePositions& /*V*/, double /*cv*/,
                                     SparseMatrix& /*J*/) const {}
  // Loads whose state is integrated in time (the gas of a chamber with inflow and outflow;
  // contact friction will be one): add() evaluates from the state committed last, so a step
  // that fails leaves it as it was. The system calls these where the analysis starts, accepts
  // a step and writes or reads a checkpoint (MechanicalSystem::accept); nothing for the others.

  /// The state at the start of the analysis, the loads at `s`.
  virtual void start(const LoadState& /*s*/) {}
  /// A step ending at `s` is accepted: the state moves on to it.
  virtual void commit(const LoadState& /*s*/) {}
  /// The committed state as numbers (a checkpoint, the next step of a staged run), and back:
  /// restore_state reads from `in` at `at`, returns the position after what it read and
  /// throws std::invalid_argument when it does not fit.
  virtual void save_state(std::vector<double>& /*out*/) const {}
  virtual size_t restore_state(const std::vector<double>& /*in*/, size_t at) { return at; }
  /// Once every load of the system is bound: the system's terms in the model's order, this
  /// one at `self` (gas chambers joined by orifices find each other).
  virtual void connect(std::span<LoadTerm* const> /*all*/, int /*self*/) {}

  /// Its account for summary.json, a JSON object (a gas chamber's mass and energy balance
  /// since the start); empty when it keeps none.
  virtual std::string account_json() const { return {}; }
  /// At the end of a completed run (a collective call on several processes): why its
  /// answer is wrong, if it is (the run then fails), after telling `warn` what is doubtful.
  virtual std::string end_check(const std::function<void(std::string)>& /*warn*/) const {
    return {};
  }

  /// A quantity of the output's history (gas_volume, gas_pressure) at the last add(); none
  /// when the load has no such quantity.
  virtual std::optional<double> quantity(std::string_view /*name*/) const { return {}; }
  /// The same at (t, x) (a collective call on several processes).
  virtual std::optional<double> quantity_at(std::string_view /*name*/, double /*t*/,
                                            const NodePositions& /*x*/) const {
    return {};
  }
  /// A per-element field of the frames (gas_pressure): writes the load's cells of
  /// `per_cell` (cells numbered through the blocks, `first_cell[b]` the first of block b);
  /// false when the load has no such field.
  virtual bool cell_field(std::string_view /*name*/, double /*t*/, const NodePositions& /*x*/,
                          std::span<const int> /*first_cell*/,
                          std::vector<double>& /*per_cell*/) const {
    return false;
  }
  /// A per-node field of the frames (contact_pressure, contact_gap): adds (the gap: takes
  /// the least of) the load's values at its nodes into `per_node` (one per node, NaN where
  /// none); false when the load has no such field.
  virtual bool node_field(std::string_view /*name*/, double /*t*/, const NodePositions& /*x*/,
                          std::vector<double>& /*per_node*/) const {
    return false;
  }
  /// The largest stiffness the load may add at a node over the node's mass (a contact
  /// penalty, active or not), for the stable step of explicit time integration; 0: none.
  virtual double max_stiffness_over_mass(std::span<const double> /*node_mass*/) const { return 0; }
  /// Motion the load's own state carries, outside the nodes (a free rigid body's rotation):
  /// its kinetic energy at the state committed last (½ ω·Iω), and the work the load's forces
  /// did on it over the last accepted step (the contact moment's, by the trapezoidal rule as
  /// the energy account books the nodes' work). Joules; 0 for a load without such a state.
  virtual double kinetic_energy() const { return 0; }
  virtual double state_work() const { return 0; }
};

/// Names element e of block b for messages (the user's id).
using ElementNamer = std::function<long(int block, int element)>;

/// A load of the model.
class Load {
 public:
  virtual ~Load() = default;
  /// Its kind as the model file names it (point, edge, pressure, gas, gravity, drag).
  virtual std::string_view kind() const = 0;
  virtual LoadOrder order() const = 0;
  virtual std::unique_ptr<Load> clone() const = 0;
  /// Set-up once the whole model is known, and again on a new reference (form finding):
  /// throws std::invalid_argument saying what is wrong (elements named by `name`, default
  /// their position in their block from 1).
  virtual void set_up(const Model& /*model*/, const ElementNamer& /*name*/ = {}) {}
  /// The load a later step goes on with when it gives no loads of its own: this one with its
  /// time dependence held at its value at t (`owner`: the model this load is in; `step`: the
  /// step's model, to which it may add time functions).
  virtual std::unique_ptr<Load> held(double t, const Model& owner, Model& step) const = 0;
  /// Cuts the load down to an MPI piece, before `whole` is cut (its mesh is still whole):
  /// `own` the piece's elements per block, `local_of` each node's index on the piece (-1:
  /// not held). False: the load has nothing on this piece (dropped).
  virtual bool keep_piece(const Model& /*whole*/, const std::vector<std::vector<int>>& /*own*/,
                          const std::vector<int>& /*local_of*/) {
    return true;
  }
  /// How the run's summary counts it on its `loads:` line (point, edge, ...; empty: not
  /// there), and a line of its own (empty: none); `index` among the loads of its kind.
  virtual std::string_view counted_as() const { return kind(); }
  virtual std::string summary(int /*index*/) const { return {}; }
  /// The load bound to an assembler of `site.model` (the model holding it, or its piece).
  virtual std::unique_ptr<LoadTerm> bind(const LoadSite& site) const = 0;
};

/// The list's nodes held on a piece, renumbered (their order kept).
void restrict_nodes(std::vector<int>& nodes, const std::vector<int>& local_of);

}  // namespace velum
