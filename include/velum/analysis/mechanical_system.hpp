// The model as a SecondOrderSystem: maps the equations to node displacements (fixed,
// prescribed and symmetry DOFs eliminated), assembles internal forces and tangents, applies
// loads with their time functions (follower pressure with its load stiffness, payload drag),
// and adds Rayleigh damping C = α M + β K. Also the bookkeeping the output needs: reactions,
// energies, current positions.
#pragma once

#include <memory>

#include "velum/assembly/assembler.hpp"
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
  const VecX& lumped_mass() const override { return lumped_eq_; }
  double force_scale() const override { return force_scale_; }
  double residual_noise() const override { return residual_noise_; }
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
  /// (Assembler::LocalShare), as reactions() below.
  const NodePositions& external_forces(double t, const VecX& u, const VecX& v);
  /// Reactions: internal minus external force at eliminated components (full, global; zero
  /// at free components). Valid after evaluate() at the same state.
  const NodePositions& last_internal() const { return Fint_; }
  const NodePositions& last_external() const { return Fext_; }

  /// Support reactions (full, global): internal minus external force at (t, u, v), kept only
  /// at eliminated components (fixed, prescribed, normal to a symmetry plane). The inertia of
  /// constrained nodes is not included. Overwrites last_internal() and last_external().
  NodePositions reactions(double t, const VecX& u, const VecX& v);

  /// Volume and absolute pressure of gas chamber i at the last evaluation of the loads.
  double gas_volume(int i) const { return gas_volume_[i]; }
  double gas_pressure(int i) const { return gas_pressure_[i]; }

  double kinetic_energy(const VecX& v) const {
    return squared_norm(v) == 0 ? 0.0 : 0.5 * dot(v, mass_times(v));
  }
  double strain_energy(double t, const VecX& u) const;

 private:
  void apply_prescribed(double t, NodePositions& U) const;
  void set_positions(double t, const VecX& u);
  // Loads at t; the follower-pressure load stiffness is subtracted from *Kload. With
  // `fused`, the pressures that cover a whole block were computed in the internal pass
  // (their forces are in Fp_).
  void assemble_external(double t, const VecX& v, SparseMatrix* Kload, bool fused = false);
  bool has_drag() const;
  // |diagonal| of a matrix on the assembler's pattern (J, T_), whole (the shares summed).
  VecX abs_diagonal(const SparseMatrix& J) const;
  double distributed_force_scale();

  const Model& model_;
  DofMap dofs_;
  Assembler assembler_;
  // Matrices on the assembler's pattern, allocated only when a run needs them: the Jacobian
  // is assembled in place (evaluate); K_ is kept apart only for stiffness-proportional
  // damping, and M_ is built on first use (a static run never needs it).
  mutable SparseMatrix M_;
  mutable bool have_mass_ = false;
  mutable SparseMatrix T_;  ///< tension stiffness (stiffen_stress_free), built on first use
  SparseMatrix K_;
  VecX lumped_nodes_, lumped_eq_;
  std::vector<int> equation_node_;  ///< node of each equation
  std::vector<NodePositions> edge_forces_;
  std::vector<NodePositions> gravity_forces_;
  NodePositions U_, V_, x_, Fint_, Fext_, Fp_;
  // Enclosed gas: volume and pressure per chamber, the volume gradient, and the rank-one
  // coupling (γ p / V) a aᵀ of each chamber as the Jacobian's low-rank part.
  std::vector<double> gas_volume_, gas_pressure_;
  NodePositions gas_gradient_;
  VecX gas_gradient_eq_;
  LowRankJacobian low_rank_;
  std::vector<double> block_pressure_;      ///< whole-block pressures at the evaluated time
  VecX fred_, mv_, mvv_, x_eq_, noise_eq_;  ///< mv_ = M a, mvv_ = M v (evaluate)
  double force_scale_ = 0, residual_noise_ = 0;
  bool drag_ = false;
};

}  // namespace velum
