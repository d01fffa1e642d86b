// The model as a SecondOrderSystem: maps the equations to node displacements (fixed,
// prescribed and symmetry DOFs eliminated), assembles internal forces and tangents, applies
// loads with their time functions (follower pressure with its load stiffness, payload drag),
// and adds Rayleigh damping C = α M + β K. Also the bookkeeping the output needs: reactions,
// energies, current positions.
#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "velum/assembly/assembler.hpp"
#include "velum/load/load.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

class MechanicalSystem final : public SecondOrderSystem {
 public:
  /// The whole model, or under mpirun a process's piece of it (share_model): its own elements
  /// and nodes.
  explicit MechanicalSystem(const Model& model);

  int size() const override { return dofs_.num_equations(); }
  void evaluate(double t, const VecX& u, const VecX& v, const VecX& a, double cu, double cv,
                double ca, VecX& r, SparseMatrix* J) override;
  const LowRankJacobian& jacobian_low_rank() const override { return low_rank_; }
  long pattern_revision() const override { return assembler_.pattern_revision(); }
  const VecX& lumped_mass() const override { return lumped_eq_; }
  double load_stiffness_over_mass() const override;
  double force_scale() const override { return force_scale_; }
  double residual_noise() const override { return residual_noise_; }
  double reference_position_norm() const override { return reference_position_norm_; }
  std::string diagnose_singular(const SparseMatrix& J) const override;
  bool stiffen_stress_free(SparseMatrix& J) const override;
  void complete(VecX& from_jacobian) const override;
  const std::vector<int>& equation_groups() const override { return equation_node_; }
  std::string inverted_element(double t_from, const VecX& u_from, double t_to,
                               const VecX& u_to) const override;
  // Several processes: the equation vectors are this process's local equations (owned,
  // then ghosts; DofMap::layout()), reduced over the owned ones.
  bool distributed() const override { return dofs_.layout().distributed(); }
  int owned_size() const override { return dofs_.layout().owned(); }
  long global_size() const override { return dofs_.global_equations(); }
  double sum_over_processes(double local) const override;
  void sum_over_processes(double* values, long n) const override;
  double max_over_processes(double local) const override;
  double global_entry(const VecX& x, int eq) const override;
  VecX to_global(const VecX& x) const override;
  VecX to_local(const VecX& whole) const override;
  const EquationLayout& layout() const { return dofs_.layout(); }

  const Model& model() const { return model_; }
  const DofMap& dofs() const { return dofs_; }
  const Assembler& assembler() const { return assembler_; }
  /// The consistent mass matrix, assembled when first asked for (a static run never needs it):
  /// on several processes, this process's share of it (see mass_times).
  const SparseMatrix& mass_matrix() const;
  /// M v, whole (summed over the processes).
  VecX mass_times(const VecX& v) const;

  /// Full nodal displacements (3 x nodes) for equation values u at time t (prescribed
  /// motions included).
  NodePositions displacements(double t, const VecX& u) const;
  NodePositions velocities(const VecX& v) const;
  /// External forces at time t for displacements u (full, global); no internal forces are
  /// assembled. Overwrites last_external(). On several processes, this process's share
  /// (Assembler::LocalShare), as reactions() below. `at_supports`: as the supports carry them
  /// (LoadState::at_supports; for the reactions), else as the residual has them.
  const NodePositions& external_forces(double t, const VecX& u, const VecX& v,
                                       bool at_supports = false);
  /// Reactions: internal minus external force at eliminated components (full, global; zero
  /// at free components). Valid after evaluate() at the same state.
  const NodePositions& last_internal() const { return Fint_; }
  /// This process's share of vᵀ M v (v over its local equations): its share of the mass
  /// matrix's product, no exchange; summed over the processes, vᵀ M v (on one process
  /// v · mass_times(v), the same bits).
  double mass_product_share(const VecX& v) const { return v.dot(mass_entries() * v); }
  const NodePositions& last_external() const { return Fext_; }
  /// Mass scaling (explicit dynamics): adds per_node (over the model's nodes) to the lumped
  /// mass and, as point masses, to the mass matrix: inertia alone, no load sees it. One
  /// process only.
  void add_node_mass(const VecX& per_node);
  /// The lumped mass of each node (the model's, plus what add_node_mass added).
  const VecX& node_mass() const { return lumped_nodes_; }
  /// Whether last_external() after an evaluate() at an accepted state is what
  /// external_forces() gives there (to round-off: the follower pressures come fused with the
  /// internal pass): no load uses the velocity, keeps a state integrated in time or a low-rank
  /// part (gas), no motion is prescribed and no section changes in time (reefing). The explicit
  /// energy account books its work from them then, without a second pass over the loads.
  bool external_forces_reusable() const { return external_reusable_; }

  /// Support reactions (full, global): internal minus external force at (t, u, v), kept only
  /// at eliminated components (fixed, prescribed, normal to a symmetry plane). The inertia of
  /// constrained nodes is not included. Overwrites last_internal() and last_external().
  NodePositions reactions(double t, const VecX& u, const VecX& v);

  /// The loads bound to this system (load/load.hpp), in the model's order.
  const std::vector<std::unique_ptr<LoadTerm>>& loads() const { return terms_; }
  /// Loads with a state integrated in time (LoadTerm::start, commit): their state at the start
  /// (t, u), and a step ending at (t, u, v) accepted. The same bits on every process.
  void start_loads(double t, const VecX& u, const VecX& v);
  /// `at_last_evaluation`: the caller's word that the last evaluate() was at this state (an
  /// explicit step ends on one evaluation, and its state is that evaluation's vector u, not
  /// changed since): the positions it set are kept instead of set again when it was an
  /// explicit step's (no Jacobian, no shift) at the same u storage and at t (or at a time
  /// that differs in its last bits, where no prescribed motion reads the time).
  void accept(double t, const VecX& u, const VecX& v, bool at_last_evaluation = false);
  /// Their committed state as numbers (checkpoints, staged runs), followed by the history of
  /// the laws that keep one per point (ElementBlock::history_size; nothing when none does),
  /// and back (throws std::invalid_argument when it does not fit these loads and blocks).
  std::vector<double> save_load_state() const;
  void restore_load_state(const std::vector<double>& state);
  /// The laws' history alone (the tail of save_load_state; empty when no law keeps one), and
  /// back from `in` at `at`: a staged step whose loads start afresh keeps its sheets' history.
  std::vector<double> save_law_history() const;
  void restore_law_history(const std::vector<double>& in, size_t at = 0);

  /// A history quantity (gas_volume, gas_pressure) of the i-th load that has it, at the last
  /// evaluation of the loads; none when fewer loads have it.
  std::optional<double> load_quantity(std::string_view name, int i) const;
  /// The same at (t, x) (a collective call on several processes).
  std::optional<double> load_quantity_at(std::string_view name, int i, double t,
                                         const NodePositions& x) const;
  /// A per-node field of the loads (LoadTerm::node_field), one value per node (NaN where no
  /// load has one); empty when no load has the field.
  std::vector<double> load_node_field(std::string_view name, double t,
                                      const NodePositions& x) const;
  /// A per-element field of the loads that have the quantity `name` (cells through the
  /// blocks; 0 where none): empty when no load has it. A collective call.
  std::vector<double> load_cell_field(std::string_view name, double t,
                                      const NodePositions& x) const;
  /// Volume and absolute pressure of gas chamber i at the last evaluation of the loads.
  double gas_volume(int i) const { return *load_quantity("gas_volume", i); }
  double gas_pressure(int i) const { return *load_quantity("gas_pressure", i); }

  double kinetic_energy(const VecX& v) const {
    return squared_norm(v) == 0 ? 0.0 : 0.5 * dot(v, mass_times(v));
  }
  /// The kinetic energy the loads' own states hold at the last accepted step (a free body's
  /// rotation), and the work the loads did on those states over that step
  /// (LoadTerm::kinetic_energy, LoadTerm::state_work).
  double load_kinetic_energy() const {
    double e = 0;
    for (const auto& term : terms_) e += term->kinetic_energy();
    return e;
  }
  double load_state_work() const {
    double w = 0;
    for (const auto& term : terms_) w += term->state_work();
    return w;
  }
  double strain_energy(double t, const VecX& u) const;
  /// The work done on the model from (t0, U0) to (t1, U1) (full displacements) by sections
  /// that change in time (a reefing line drawn in, a line cut): the trapezoidal rule on their
  /// strain energy's change in time at fixed positions; 0 without such sections. A collective
  /// call on several processes.
  double section_work(double t0, const NodePositions& U0, double t1, const NodePositions& U1) const;

 private:
  void apply_prescribed(double t, NodePositions& U) const;
  void set_positions(double t, const VecX& u);
  // The loads' couplings beyond the elements at x_ (LoadTerm::update_couplings): when they
  // changed, the assembler's pattern anew and the matrices on it made again.
  void update_couplings();
  // Loads at t; their load stiffness is subtracted from *Kload. With `fused`, the pressures
  // that cover a whole block were computed in the internal pass (their forces are in Fp_).
  // `at_supports`: LoadState::at_supports (the reactions' forces).
  void assemble_external(double t, const VecX& v, SparseMatrix* Kload, bool fused = false,
                         bool at_supports = false);
  // |diagonal| of a matrix on the assembler's pattern (J, the tension stiffness), whole (the
  // shares summed).
  VecX abs_diagonal(const SparseMatrix& J) const;
  const SparseMatrix& mass_entries() const;  ///< mass_matrix() without its pattern's zeros
  double distributed_force_scale();

  const Model& model_;
  DofMap dofs_;
  Assembler assembler_;
  // Matrices on the assembler's pattern, allocated only when a run needs them: the Jacobian
  // is assembled in place (evaluate); K_ is kept apart only for stiffness-proportional
  // damping, and M_ is built on first use (a static run never needs it).
  mutable SparseMatrix M_;
  mutable SparseMatrix M_entries_;  ///< M_ without the zeros of its pattern (products)
  mutable bool have_mass_ = false;
  SparseMatrix K_;
  VecX lumped_nodes_, lumped_eq_;
  VecX added_nodes_;                              ///< add_node_mass (empty: none)
  std::vector<int> equation_node_;                ///< node of each equation
  std::vector<std::unique_ptr<LoadTerm>> terms_;  ///< the model's loads, bound
  int low_rank_columns_ = 0;                      ///< of all loads (a gas chamber: one)
  bool velocity_ = false;                         ///< some load uses the velocity
  bool external_reusable_ = false;                ///< external_forces_reusable()
  NodePositions U_, V_, x_, Fint_, Fext_, Fp_;
  LowRankJacobian low_rank_;
  /// The loads' couplings (update_couplings).
  std::vector<std::array<int, 2>> couplings_;
  std::vector<double> block_pressure_;      ///< whole-block pressures at the evaluated time
  VecX fred_, mv_, mvv_, x_eq_, noise_eq_;  ///< mv_ = M a, mvv_ = M v (evaluate)
  double force_scale_ = 0, residual_noise_ = 0;
  struct {  ///< where the last explicit-step evaluation set x_ (u's storage and size, t)
    const double* u = nullptr;
    Eigen::Index size = 0;
    double t = 0;
  } explicit_at_;
  double reference_position_norm_ = 0;
};

}  // namespace velum
