// The one interface through which time integrators meet the physics (as PETSc's TS and
// MFEM's ImplicitSolve): the residual of M a + C v + f_int(u) − f_ext(t, u, v) = 0 and its
// shifted Jacobian cu ∂r/∂u + cv ∂r/∂v + ca ∂r/∂a. Integrators never see elements.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "velum/math/sparse.hpp"
#include "velum/math/types.hpp"

namespace velum {

/// A part of the Jacobian kept out of the sparse matrix: the full Jacobian is J + U Wᵀ, with
/// a few dense columns (an enclosed gas couples every node of its chamber through p(V): one
/// column each). Newton applies it on J's factorisation (Sherman-Morrison-Woodbury), so the
/// sparse matrix never holds a dense block.
struct LowRankJacobian {
  MatX U, W;  ///< size() x k each; k = 0: none
};

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int size() const = 0;
  /// Residual r (and, when J != null, the shifted Jacobian, pattern fixed) at time t.
  virtual void evaluate(double t, const VecX& u, const VecX& v, const VecX& a, double cu, double cv,
                        double ca, VecX& r, SparseMatrix* J) = 0;
  /// The low-rank part of the Jacobian of the last evaluate() that asked for one (same shift).
  virtual const LowRankJacobian& jacobian_low_rank() const {
    static const LowRankJacobian kNone;
    return kNone;
  }
  /// The revision of the last Jacobian's sparsity pattern (0: the pattern never changes; a
  /// contact's couplings change it): a solver analyses anew when it changes
  /// (LinearSolver::refactorize).
  virtual long pattern_revision() const { return 0; }
  /// Lumped (diagonal) mass per equation, for explicit integration.
  virtual const VecX& lumped_mass() const = 0;
  /// The largest stiffness over mass that loads may add at a node beyond the last Jacobian's
  /// (a contact penalty not active yet), for the stable step of explicit integration.
  virtual double load_stiffness_over_mass() const { return 0; }
  /// A force scale of the last evaluation (norms of internal and external forces), against
  /// which residuals are judged. Not a number after an explicit step's evaluation (no
  /// Jacobian, no shift) on several processes, where nothing judges a residual.
  virtual double force_scale() const = 0;
  /// The round-off level of the last residual that came with a Jacobian: how much the forces
  /// change when every coordinate moves by one unit in the last place (ε ‖|K|ᵀ |x|‖). No
  /// residual below it can be told from zero. 0 when unknown.
  virtual double residual_noise() const { return 0; }
  /// The norm of the positions that u = 0 stands for (the reference configuration's
  /// coordinates, over the equations): a displacement is resolved only to ε times the
  /// position it moves, so far from the origin no iterate settles closer than that. 0 when
  /// the unknowns are not displacements from positions.
  virtual double reference_position_norm() const { return 0; }
  /// Equations that move together (the components of one node), as a group index per
  /// equation; empty when every equation stands alone. Dynamic relaxation gives each group
  /// one fictitious mass, so that a direction without stiffness yet (the normal of a flat,
  /// unstressed sheet) moves with its node's in-plane mass.
  virtual const std::vector<int>& equation_groups() const {
    static const std::vector<int> none;
    return none;
  }
  /// Empty when no element turns inside out between the states (t_from, u_from) and (t_to,
  /// u_to) (a surface normal or a line's axis reversing or collapsing at a point); else says
  /// which. A state reached that way is not a solution to keep, however small its residual.
  virtual std::string inverted_element(double t_from, const VecX& u_from, double t_to,
                                       const VecX& u_to) const {
    (void)t_from, (void)u_from, (void)t_to, (void)u_to;
    return {};
  }
  /// Names the equations of J that carry no stiffness and no mass, and what to do about them;
  /// empty when there are none.
  virtual std::string diagnose_singular(const SparseMatrix& J) const = 0;
  /// For Newton's first correction from a state that carries no stress at all (the state
  /// evaluated last, J its Jacobian: the internal forces of that evaluation are read), whose
  /// Jacobian has next to no stiffness in some directions (a sheet normal to itself where it is
  /// flat or shallow, a cable across itself where it is straight: the correction there overshoots
  /// by orders of magnitude): adds to J the geometric stiffness of a small uniform tension and
  /// returns true. The correction then has the shape a taut sheet takes, and its size is the
  /// line search's to find. Otherwise returns false and leaves J as it is.
  virtual bool stiffen_stress_free(SparseMatrix& J) const {
    (void)J;
    return false;
  }
  /// Completes a vector computed from the Jacobian this system assembled (J x, row sums of
  /// |J|): on several processes each holds its share of J, and the shares' vectors are summed
  /// here (every process then holds the same whole vector). Nothing on one process.
  virtual void complete(VecX& from_jacobian) const { (void)from_jacobian; }

  // Reductions over the equations. On several processes (docs/parallel.md) each holds the
  // equations it owns, first, then ghost copies of equations another process owns: a sum
  // over the equations is a sum over each process's owned ones, summed over the processes
  // (the same bits on every process, so that every process takes the same decisions). On
  // one process these are Eigen's own (the same bits as before they existed).

  /// Whether the equation vectors are distributed (owned equations and ghosts).
  virtual bool distributed() const { return false; }
  /// Equations this process owns: the first owned_size() entries of an equation vector.
  virtual int owned_size() const { return size(); }
  /// Equations over all the processes.
  virtual long global_size() const { return size(); }
  /// Sum (max) over the processes of each one's `local`, the same on every process.
  virtual double sum_over_processes(double local) const { return local; }
  /// Each entry summed over the processes, in one reduction (nothing on one process).
  virtual void sum_over_processes(double* values, long n) const { (void)values, (void)n; }
  virtual double max_over_processes(double local) const { return local; }
  /// Entry `eq` of the global numbering of x (the owner's value, on every process).
  virtual double global_entry(const VecX& x, int eq) const { return x[eq]; }

  /// An equation vector in the global numbering, whole, on the first process (empty on the
  /// others; a collective call): what a checkpoint writes. x itself on one process.
  virtual VecX to_global(const VecX& x) const { return x; }
  /// This process's equations of a whole vector in the global numbering (every process
  /// holds it: a checkpoint read back). `whole` itself on one process.
  virtual VecX to_local(const VecX& whole) const { return whole; }

  // Templates: an expression is reduced as it stands (a temporary of it could round
  // differently where the compiler fuses a multiply and an add).
  template <class A, class B>
  double dot(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) const {
    if (!distributed()) return a.dot(b);
    const int n = owned_size();
    return sum_over_processes(a.head(n).dot(b.head(n)));
  }
  template <class A>
  double squared_norm(const Eigen::MatrixBase<A>& a) const {
    return distributed() ? dot(a, a) : a.squaredNorm();
  }
  template <class A>
  double norm(const Eigen::MatrixBase<A>& a) const {
    return distributed() ? std::sqrt(dot(a, a)) : a.norm();
  }
  /// The largest |entry| (0 for none).
  template <class A>
  double max_abs(const Eigen::MatrixBase<A>& a) const {
    if (!distributed()) return a.size() ? a.cwiseAbs().maxCoeff() : 0.0;
    const int n = owned_size();
    return max_over_processes(n > 0 ? a.head(n).cwiseAbs().maxCoeff() : 0.0);
  }
  /// Whether every entry is finite, on every process.
  template <class A>
  bool all_finite(const Eigen::MatrixBase<A>& a) const {
    if (!distributed()) return a.allFinite();
    return max_over_processes(a.allFinite() ? 0.0 : 1.0) == 0.0;
  }
  /// The sum of every entry.
  template <class A>
  double sum(const Eigen::MatrixBase<A>& a) const {
    return distributed() ? sum_over_processes(a.head(owned_size()).sum()) : a.sum();
  }
  /// Wᵀ Z over the equations (Z: columns of equation vectors, or one).
  template <class Z>
  typename Z::PlainObject transposed_product(const MatX& W, const Eigen::MatrixBase<Z>& z) const {
    if (!distributed()) return W.transpose() * z;
    const int n = owned_size();
    typename Z::PlainObject p = W.topRows(n).transpose() * z.topRows(n);
    sum_over_processes(p.data(), static_cast<long>(p.size()));
    return p;
  }
};

}  // namespace velum
