// The direct solvers behind LinearSolver on small matrices of each kind the analyses produce:
// symmetric positive definite, symmetric indefinite (a slack membrane under pressure) and
// unsymmetric (a follower pressure on a free edge). Also which back-end `auto` picks.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "velum/solve/linear_solver.hpp"

namespace velum {
namespace {

// 2-D Laplacian on an m x m grid (SPD), minus `shift` on the diagonal, plus `skew` times an
// antisymmetric coupling between horizontal neighbours.
SparseMatrix grid_matrix(int m, double shift, double skew) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return i + m * j; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      t.emplace_back(id(i, j), id(i, j), 4.0 - shift + 0.01 * i);
      if (i + 1 < m) {
        t.emplace_back(id(i, j), id(i + 1, j), -1.0 + skew);
        t.emplace_back(id(i + 1, j), id(i, j), -1.0 - skew);
      }
      if (j + 1 < m) {
        t.emplace_back(id(i, j), id(i, j + 1), -1.0);
        t.emplace_back(id(i, j + 1), id(i, j), -1.0);
      }
    }
  SparseMatrix A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

double solve_residual(LinearSolver& s, const SparseMatrix& A) {
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  Eigen::VectorXd x;
  if (!s.refactorize(A) || !s.solve(b, x)) return 1e300;
  return (A * x - b).norm() / b.norm();
}

std::vector<SolverKind> kinds() {
  std::vector<SolverKind> k = {SolverKind::kAuto, SolverKind::kUmfpack, SolverKind::kKlu};
  if (have_mumps()) k.push_back(SolverKind::kMumps);
  return k;
}

TEST(Solver, EveryBackEndSolvesDefiniteIndefiniteAndUnsymmetric) {
  const SparseMatrix spd = grid_matrix(30, 0.0, 0.0);
  const SparseMatrix indefinite = grid_matrix(30, 3.0, 0.0);  // eigenvalues of both signs
  const SparseMatrix unsym = grid_matrix(30, 0.0, 0.3);
  for (SolverKind k : kinds()) {
    for (const SparseMatrix* A : {&spd, &indefinite, &unsym}) {
      auto s = make_linear_solver(k);
      EXPECT_LT(solve_residual(*s, *A), 1e-10) << s->name();
    }
  }
  auto chol = make_linear_solver(SolverKind::kCholmod);
  EXPECT_LT(solve_residual(*chol, spd), 1e-12);
  auto chol2 = make_linear_solver(SolverKind::kCholmod);
  EXPECT_FALSE(chol2->refactorize(indefinite)) << "CHOLMOD must refuse an indefinite matrix";
}

TEST(Solver, AutoPicksTheSymmetricFactorisationWhenItCan) {
  auto s = make_linear_solver(SolverKind::kAuto);
  ASSERT_LT(solve_residual(*s, grid_matrix(20, 0.0, 0.0)), 1e-12);
  EXPECT_EQ(s->name(), have_mumps() ? "supernodal-cholesky" : "cholmod");
  // Same pattern, indefinite values: MUMPS's LDLᵀ (pivoting), or LU without MUMPS.
  ASSERT_LT(solve_residual(*s, grid_matrix(20, 3.0, 0.0)), 1e-10);
  EXPECT_EQ(s->name(), have_mumps() ? "mumps" : "supernodal-lu");
  // Unsymmetric values on the same pattern: LU, by the supernodal LU at this size.
  ASSERT_LT(solve_residual(*s, grid_matrix(20, 0.0, 0.3)), 1e-10);
  EXPECT_EQ(s->name(), "supernodal-lu");
  // And back: MUMPS's LDLᵀ for one factorisation after the indefinite matrix (the Cholesky's
  // back-off), then the Cholesky.
  ASSERT_LT(solve_residual(*s, grid_matrix(20, 0.0, 0.0)), 1e-12);
  if (have_mumps()) {
    EXPECT_EQ(s->name(), "mumps");
    ASSERT_LT(solve_residual(*s, grid_matrix(20, 0.0, 0.0)), 1e-12);
    EXPECT_EQ(s->name(), "supernodal-cholesky");
  }
  EXPECT_EQ(s->analyses(), 1) << "one pattern, one analysis at this level";
  EXPECT_EQ(s->factorizations(), have_mumps() ? 5 : 4);
  // A larger unsymmetric matrix: the supernodal LU too (UMFPACK above 125,000 equations).
  auto large = make_linear_solver(SolverKind::kAuto);
  ASSERT_LT(solve_residual(*large, grid_matrix(80, 0.0, 0.3)), 1e-10);
  EXPECT_EQ(large->name(), "supernodal-lu");
}

// MUMPS factorises a symmetric matrix without pivoting first. Here the first pivot of each
// 2 x 2 block is tiny and positive: without pivoting the second is -1e12 and the solution is
// wrong in its fifth digit; the negative pivot must send it back to threshold pivoting.
TEST(Solver, MumpsPivotsWhenTheMatrixIsIndefinite) {
  if (!have_mumps()) GTEST_SKIP() << "built without MUMPS";
  const int blocks = 50;
  std::vector<Eigen::Triplet<double>> t;
  for (int b = 0; b < blocks; ++b) {
    const int i = 2 * b;
    t.emplace_back(i, i, 1e-12);
    t.emplace_back(i + 1, i + 1, 1e-12 * (b + 1));
    t.emplace_back(i, i + 1, 1.0);
    t.emplace_back(i + 1, i, 1.0);
    if (b + 1 < blocks) t.emplace_back(i + 1, i + 2, 1e-3), t.emplace_back(i + 2, i + 1, 1e-3);
  }
  SparseMatrix A(2 * blocks, 2 * blocks);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  for (SolverKind k : {SolverKind::kMumps, SolverKind::kAuto}) {
    auto s = make_linear_solver(k);
    for (int repeat = 0; repeat < 3; ++repeat)  // also after the first fallback
      EXPECT_LT(solve_residual(*s, A), 1e-12) << s->name() << ", factorisation " << repeat;
    // A definite matrix after it is solved as well (without pivoting or with).
    EXPECT_LT(solve_residual(*s, grid_matrix(10, 0.0, 0.0)), 1e-12) << s->name();
  }
}

// CHOLMOD reads one triangle: an unsymmetric matrix given to it by the user's choice must stop
// the run with a message that says so, not be factorised as another (symmetric) matrix.
TEST(Solver, CholmodRefusesAnUnsymmetricMatrix) {
  auto s = make_linear_solver(SolverKind::kCholmod);
  ASSERT_LT(solve_residual(*s, grid_matrix(10, 0.0, 0.0)), 1e-12);
  try {
    s->refactorize(grid_matrix(10, 0.0, 1e-6));  // same pattern, unsymmetric values
    ADD_FAILURE() << "CHOLMOD accepted an unsymmetric matrix";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unsymmetric"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("linear_solver: auto"), std::string::npos) << e.what();
  }
  // Round-off asymmetry (1e-14 of the entries) is symmetric enough.
  EXPECT_LT(solve_residual(*s, grid_matrix(10, 0.0, 1e-14)), 1e-12);
}

// KLU reuses the pivot order of its last full factorisation while it stays stable: a matrix on
// the same pattern whose old pivots are tiny (1e-14 on the diagonal) must be factorised again
// with pivoting, and solved as accurately.
TEST(Solver, KluRefactorisationFallsBackToPivotingWhenThePivotsDegrade) {
  const int blocks = 40;
  auto matrix = [&](double diag, double off) {
    std::vector<Eigen::Triplet<double>> t;
    for (int b = 0; b < blocks; ++b) {
      const int i = 2 * b;
      t.emplace_back(i, i, diag);
      t.emplace_back(i + 1, i + 1, 1.0 + 0.01 * b);
      t.emplace_back(i, i + 1, off);
      t.emplace_back(i + 1, i, off);
      if (b + 1 < blocks) t.emplace_back(i + 1, i + 2, 0.1), t.emplace_back(i + 2, i + 1, 0.2);
    }
    SparseMatrix A(2 * blocks, 2 * blocks);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
  };
  auto s = make_linear_solver(SolverKind::kKlu);
  EXPECT_LT(solve_residual(*s, matrix(2.0, 0.5)), 1e-14);    // diagonal pivots
  EXPECT_LT(solve_residual(*s, matrix(2.1, 0.52)), 1e-14);   // reused
  EXPECT_LT(solve_residual(*s, matrix(1e-14, 1.0)), 1e-14);  // old pivots unstable: pivoting
  EXPECT_LT(solve_residual(*s, matrix(1e-14, 1.1)), 1e-14);  // the new order, reused
  EXPECT_LT(solve_residual(*s, matrix(2.0, 0.5)), 1e-14);
  EXPECT_EQ(s->analyses(), 1);
}

TEST(Solver, SingularMatrixIsReportedNotSolved) {
  SparseMatrix A = grid_matrix(10, 0.0, 0.0);
  // Row and column 0 zero: a DOF without stiffness (the diagonal entry stays in the pattern).
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (it.row() == 0 || it.col() == 0) it.valueRef() = 0.0;
  for (SolverKind k :
       {SolverKind::kAuto, SolverKind::kUmfpack, SolverKind::kKlu, SolverKind::kMumps}) {
    if (k == SolverKind::kMumps && !have_mumps()) continue;
    auto s = make_linear_solver(k);
    Eigen::VectorXd x, b = Eigen::VectorXd::Ones(A.rows());
    const bool ok = s->refactorize(A) && s->solve(b, x) && (A * x - b).norm() < 1e-8;
    EXPECT_FALSE(ok) << s->name() << " claimed to solve a singular system";
    EXPECT_FALSE(s->status().empty()) << s->name() << " gave no reason";
  }
}

}  // namespace
}  // namespace velum
