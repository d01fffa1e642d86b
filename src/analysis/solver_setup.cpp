// The linear solver a run uses. PETSc's needs more than a kind: the rigid-body modes over the
// equations (the near-null space of an elastic body, from which algebraic multigrid builds
// its coarse spaces) and whether the equations come three to a node (block size 3).
#include "velum/analysis/analysis.hpp"
#include "velum/solve/petsc_solver.hpp"

namespace velum {
namespace {

// Three translations and three rotations about the origin, in each node's equation frame.
MatX rigid_body_modes(const MechanicalSystem& sys) {
  const Model& m = sys.model();
  const DofMap& dofs = sys.dofs();
  MatX modes = MatX::Zero(sys.size(), 6);
  for (int n = 0; n < m.num_nodes(); ++n) {
    const Vec3 X = m.X.col(n);
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = Vec3::Unit(k);
      const Vec3 shift = dofs.to_local(n, axis), turn = dofs.to_local(n, axis.cross(X));
      for (int c = 0; c < 3; ++c)
        if (const int e = dofs.equation(n, c); e >= 0) {
          modes(e, k) = shift[c];
          modes(e, 3 + k) = turn[c];
        }
    }
  }
  return modes;
}

// 3 when equations 3k .. 3k+2 belong to one node for every k.
int block_size(const MechanicalSystem& sys) {
  const std::vector<int>& node = sys.equation_groups();
  if (node.size() % 3 != 0) return 1;
  for (size_t e = 0; e < node.size(); e += 3)
    if (node[e + 1] != node[e] || node[e + 2] != node[e]) return 1;
  return 3;
}

}  // namespace

std::unique_ptr<LinearSolver> make_solver(const MechanicalSystem& system,
                                          const AnalysisSettings& s) {
  if (s.solver != SolverKind::kPetsc) return make_linear_solver(s.solver);
  PetscSolverSettings ps;
  ps.options = s.petsc_options;
  ps.near_null_space = [&system] { return rigid_body_modes(system); };
  // Several processes: a global property of the numbering (every process the same).
  ps.block_size = system.distributed() ? (system.dofs().whole_nodes() ? 3 : 1) : block_size(system);
  ps.layout = &system.layout();
  return make_petsc_solver(ps);
}

}  // namespace velum
