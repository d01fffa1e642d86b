// A contact term's forces and matrix on their own, for the finite-difference checks of the
// contact tests: the load term `i` of `sys` (kLastTerm: the last one) at displacements u; and
// the residuals of a system and of one restored from its saved load state.
#pragma once

#include <cstddef>
#include <limits>

#include "velum/analysis/mechanical_system.hpp"

namespace velum {

inline constexpr size_t kLastTerm = std::numeric_limits<size_t>::max();

// The term's forces over the equations at u, and with J its matrix K − ∂f/∂u with the
// low-rank part (as the system hands it to the solver), at time t. The low-rank columns start
// filled with 7: the term must zero its own.
inline VecX term_forces(MechanicalSystem& sys, size_t i, const VecX& u, MatX* J, double t = 0) {
  const Model& m = sys.model();
  LoadTerm& term = *sys.loads()[i == kLastTerm ? sys.loads().size() - 1 : i];
  NodePositions U = NodePositions::Zero(3, m.num_nodes());
  sys.dofs().scatter(u, U);
  const NodePositions x = m.X + U, V = NodePositions::Zero(3, m.num_nodes());
  NodePositions F = NodePositions::Zero(3, m.num_nodes());
  SparseMatrix K;
  LowRankJacobian L;
  const int cols = term.low_rank_columns();
  if (J) {
    sys.assembler().make_matrix(K);
    L.U.setConstant(sys.size(), cols, 7.0);
    L.W.setConstant(sys.size(), cols, 7.0);
  }
  LoadOutput out{.F = F, .K = J ? &K : nullptr, .low_rank = &L, .column = 0};
  term.add(LoadState{.t = t, .x = x, .V = V}, out);
  if (J) *J = MatX(K) + L.U * L.W.transpose();
  VecX f;
  sys.dofs().gather(F, f);
  return f;
}

// max |J + ∂f/∂u| / max |∂f/∂u| for term i at u, J its matrix there (term_forces), by central
// differences of step h (at time t).
inline double term_matrix_error(MechanicalSystem& sys, size_t i, const VecX& u, const MatX& J,
                                double h, double t = 0) {
  const Eigen::Index n = u.size();
  MatX fd(n, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    VecX e = VecX::Zero(n);
    e[k] = h;
    fd.col(k) =
        (term_forces(sys, i, u + e, nullptr, t) - term_forces(sys, i, u - e, nullptr, t)) / (2 * h);
  }
  return (J + fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
}

// The residuals at rest of `a`, started at t = 0 and `accepted` steps accepted there, and of
// `b`, restored from a's saved load state (the checkpoint tests: b must go on where a is).
inline void residuals_after_restore(MechanicalSystem& a, MechanicalSystem& b, VecX& ra, VecX& rb,
                                    int accepted = 0) {
  const VecX zero = VecX::Zero(a.size());
  a.start_loads(0.0, zero, zero);
  for (int k = 0; k < accepted; ++k) a.accept(0.0, zero, zero);
  b.restore_load_state(a.save_load_state());
  a.evaluate(0.0, zero, zero, zero, 1, 0, 0, ra, nullptr);
  b.evaluate(0.0, zero, zero, zero, 1, 0, 0, rb, nullptr);
}

}  // namespace velum
