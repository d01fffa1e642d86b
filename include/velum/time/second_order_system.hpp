// The one interface through which time integrators meet the physics (as PETSc's TS and
// MFEM's ImplicitSolve): the residual of M a + C v + f_int(u) − f_ext(t, u, v) = 0 and its
// shifted Jacobian cu ∂r/∂u + cv ∂r/∂v + ca ∂r/∂a. Integrators never see elements.
#pragma once

#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "velum/math/types.hpp"

namespace velum {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int size() const = 0;
  /// Residual r (and, when J != null, the shifted Jacobian, pattern fixed) at time t.
  virtual void evaluate(double t, const VecX& u, const VecX& v, const VecX& a, double cu, double cv,
                        double ca, VecX& r, SparseMatrix* J) = 0;
  /// Lumped (diagonal) mass per equation, for explicit integration.
  virtual const VecX& lumped_mass() const = 0;
  /// A force scale of the last evaluation (norms of internal and external forces), against
  /// which residuals are judged.
  virtual double force_scale() const = 0;
  /// The round-off level of the last residual that came with a Jacobian: how much the forces
  /// change when every coordinate moves by one unit in the last place (ε ‖|K|ᵀ |x|‖). No
  /// residual below it can be told from zero. 0 when unknown.
  virtual double residual_noise() const { return 0; }
  /// Equations that move together (the components of one node), as a group index per
  /// equation; empty when every equation stands alone. Dynamic relaxation gives each group
  /// one fictitious mass, so that a direction without stiffness yet (the normal of a flat,
  /// unstressed sheet) moves with its node's in-plane mass.
  virtual const std::vector<int>& equation_groups() const {
    static const std::vector<int> none;
    return none;
  }
  /// Names the equations of J that carry no stiffness and no mass, and what to do about them;
  /// empty when there are none.
  virtual std::string diagnose_singular(const SparseMatrix& J) const = 0;
};

}  // namespace velum
