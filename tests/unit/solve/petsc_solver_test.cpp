// linear_solver petsc on one process: the direct default (MUMPS through PETSc, LDLᵀ while
// symmetric with its inertia, LU otherwise), the iterative option (GMRES, right-preconditioned
// GAMG with a near-null space) and the failures that must be reported, never returned as NaN.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <vector>

#include "velum/parallel/processes.hpp"
#include "velum/solve/petsc_solver.hpp"

namespace velum {
namespace {

// 2-D Laplacian on an m x m grid, minus `shift` on the diagonal, plus `skew` times an
// antisymmetric coupling between horizontal neighbours; `copies` unknowns per grid point
// (uncoupled), numbered point by point.
SparseMatrix grid_matrix(int m, double shift, double skew, int copies = 1) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m, copies](int i, int j, int c) { return copies * (i + m * j) + c; };
  for (int c = 0; c < copies; ++c)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        t.emplace_back(id(i, j, c), id(i, j, c), 4.0 - shift + 0.01 * i + 0.1 * c);
        if (i + 1 < m) {
          t.emplace_back(id(i, j, c), id(i + 1, j, c), -1.0 + skew);
          t.emplace_back(id(i + 1, j, c), id(i, j, c), -1.0 - skew);
        }
        if (j + 1 < m) {
          t.emplace_back(id(i, j, c), id(i, j + 1, c), -1.0);
          t.emplace_back(id(i, j + 1, c), id(i, j, c), -1.0);
        }
      }
  SparseMatrix A(copies * m * m, copies * m * m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

double residual(LinearSolver& s, const SparseMatrix& A) {
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  Eigen::VectorXd x;
  if (!s.refactorize(A) || !s.solve(b, x)) return 1e300;
  return (A * x - b).norm() / b.norm();
}

TEST(PetscSolver, DirectSolvesDefiniteIndefiniteAndUnsymmetricWithInertia) {
  if (!processes::have_petsc()) GTEST_SKIP() << "built without PETSc";
  const SparseMatrix spd = grid_matrix(12, 0.0, 0.0);
  const SparseMatrix indefinite = grid_matrix(12, 3.0, 0.0);
  const SparseMatrix unsym = grid_matrix(12, 0.0, 0.3);
  auto s = make_petsc_solver({});
  EXPECT_LT(residual(*s, spd), 1e-12);
  EXPECT_EQ(s->negative_pivots(), 0);
  EXPECT_LT(residual(*s, indefinite), 1e-12);
  const Eigen::VectorXd eig =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(indefinite)).eigenvalues();
  const int negative = static_cast<int>((eig.array() < 0).count());
  ASSERT_GT(negative, 0);
  EXPECT_EQ(s->negative_pivots(), negative);  // LDLᵀ's inertia (Sylvester)
  EXPECT_LT(residual(*s, unsym), 1e-12);      // LU: same pattern, unsymmetric values
  EXPECT_EQ(s->negative_pivots(), -1);
  EXPECT_EQ(s->analyses(), 1);  // the pattern held: one analysis for three factorisations
  EXPECT_EQ(s->name(), "petsc (mumps)");
}

TEST(PetscSolver, SingularMatrixFailsWithAStatusNeverNaN) {
  if (!processes::have_petsc()) GTEST_SKIP() << "built without PETSc";
  SparseMatrix A = grid_matrix(6, 0.0, 0.0);
  // Zero row and column 7 (kept in the pattern): exactly singular.
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (it.row() == 7 || it.col() == 7) it.valueRef() = 0;
  auto s = make_petsc_solver({});
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(A.rows());
  Eigen::VectorXd x;
  const bool solved = s->refactorize(A) && s->solve(b, x);
  EXPECT_FALSE(solved);
  EXPECT_FALSE(s->status().empty());
}

TEST(PetscSolver, GmresWithGamgAndNearNullSpaceConvergesOrSaysWhy) {
  if (!processes::have_petsc()) GTEST_SKIP() << "built without PETSc";
  const SparseMatrix A = grid_matrix(20, 0.0, 0.0, 3);
  PetscSolverSettings ps;
  ps.options = "-ksp_type gmres -pc_type gamg -ksp_rtol 1e-10";
  ps.block_size = 3;
  const Eigen::Index n = A.rows();
  ps.near_null_space = [n] {
    MatX modes = MatX::Zero(n, 3);
    for (Eigen::Index e = 0; e < n; ++e) modes(e, e % 3) = 1.0;
    return modes;
  };
  auto s = make_petsc_solver(ps);
  EXPECT_LT(residual(*s, A), 1e-9) << s->status();
  EXPECT_EQ(s->name(), "petsc (gmres + gamg)");
  // Two iterations cannot converge: reported, not returned.
  ps.options = "-ksp_type gmres -pc_type jacobi -ksp_max_it 2";
  auto capped = make_petsc_solver(ps);
  EXPECT_EQ(residual(*capped, A), 1e300);
  EXPECT_NE(capped->status().find("did not converge"), std::string::npos) << capped->status();
}

TEST(PetscSolver, BadOptionsAreAnError) {
  if (!processes::have_petsc()) GTEST_SKIP() << "built without PETSc";
  PetscSolverSettings ps;
  ps.options = "-ksp_type no_such_method";
  auto s = make_petsc_solver(ps);
  EXPECT_FALSE(s->refactorize(grid_matrix(4, 0.0, 0.0)));
  EXPECT_NE(s->status().find("PETSc"), std::string::npos);
}

}  // namespace
}  // namespace velum
