// The supernodal LU (src/solve/supernodal_lu.hpp) on matrices built like membrane Jacobians:
// three equations per node of a quad mesh, every equation of a node coupled with every
// equation of the nodes that share an element with it, unsymmetric values with a dominant
// diagonal; some equations removed (constrained components). Against KLU and a dense LU; the
// refusals that send `auto` to KLU's full pivoting; a singular matrix.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <limits>
#include <random>
#include <vector>

#include "membrane_grid.hpp"
#include "solve/supernodal_lu.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {
namespace {

// An nx x ny grid of nodes, quad4 elements, 3 equations per node (every `drop`-th equation
// removed when drop > 0), random values in [-1, 1], each diagonal entry `dominance` times
// its column's off-diagonal sum plus one.
SparseMatrix membrane_matrix(int nx, int ny, unsigned seed, int drop = 0, double dominance = 0.5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const MembraneGrid grid(nx, ny, drop);
  const int n = grid.n;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> column_sum(n, 0.0);
  grid.for_each_coupling([&](int r, int c) {
    const double v = u(rng);
    t.emplace_back(r, c, v);
    column_sum[c] += std::abs(v);
  });
  for (int c = 0; c < n; ++c) t.emplace_back(c, c, dominance * column_sum[c] + 1.0);
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// Sets the entries of A coupling the equations of the first supernode of st (kept in the
// pattern) to 0, and their diagonal to `diagonal`: with 0 its pivots can only come from rows
// of other supernodes; with a tiny value its multipliers grow without bound.
void set_first_diagonal_block(const SupernodalStructure& st, double diagonal, SparseMatrix& A) {
  std::vector<char> in_first(A.rows(), 0);
  for (int k = st.first[0]; k < st.first[1]; ++k) in_first[st.order[k]] = 1;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (in_first[it.row()] && in_first[j]) it.valueRef() = it.row() == j ? diagonal : 0.0;
}

TEST(SupernodalLu, SolvesMembraneMatricesLikeKluAndDenseLu) {
  for (const int drop : {0, 7}) {
    const SparseMatrix A = membrane_matrix(14, 11, 3, drop);
    SupernodalLu lu;
    ASSERT_TRUE(lu.refactorize(A)) << lu.status();
    Eigen::VectorXd x, y;
    const Eigen::VectorXd b = rhs(A.rows());
    ASSERT_TRUE(lu.solve(b, x));
    EXPECT_LE(relative_residual(A, x, b), 1e-13);
    auto klu = make_linear_solver(SolverKind::kKlu);
    ASSERT_TRUE(klu->refactorize(A) && klu->solve(b, y));
    EXPECT_LE((x - y).norm(), 1e-11 * y.norm());
    // Row-major: libgmsh, linked into this test program, has its own (differently aligned)
    // PartialPivLU<MatrixXd>, and the dynamic linker would give it this program's copy.
    using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::VectorXd dense = RowMajorMatrix(A).partialPivLu().solve(b);
    EXPECT_LE((x - dense).norm(), 1e-11 * dense.norm());
    // Supernodes at least node-sized where no equation was removed, and some wider.
    const SupernodalStructure& st = lu.structure();
    EXPECT_LT(st.supernodes(), A.rows() / 3 + 1);
    EXPECT_GT(st.widest, 3);
  }
}

TEST(SupernodalLu, RefactorisesNewValuesOnTheSamePattern) {
  const SparseMatrix A = membrane_matrix(12, 12, 5, 5);
  SparseMatrix B = membrane_matrix(12, 12, 6, 5);  // same pattern, other values
  ASSERT_EQ(A.nonZeros(), B.nonZeros());
  SupernodalLu lu;
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x;
  ASSERT_TRUE(lu.refactorize(A) && lu.solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
  ASSERT_TRUE(lu.refactorize(B) && lu.solve(b, x));
  EXPECT_LE(relative_residual(B, x, b), 1e-13);
  EXPECT_EQ(lu.analyses(), 1);
  // Weak diagonals: rows exchanged within the diagonal blocks, still accurate.
  SparseMatrix C = membrane_matrix(12, 12, 7, 5, 0.02);
  ASSERT_TRUE(lu.refactorize(C)) << lu.status();
  ASSERT_TRUE(lu.solve(b, x));
  EXPECT_LE(relative_residual(C, x, b), 1e-13);
  EXPECT_EQ(lu.analyses(), 1);
}

// The first supernode's diagonal block set to zero (kept in the pattern): its pivots can only
// come from rows of other supernodes. The supernodal LU refuses; `auto` solves it through KLU.
TEST(SupernodalLu, RefusesAPivotOutsideItsBlockAndAutoFallsBackToKlu) {
  SparseMatrix A = membrane_matrix(10, 9, 11, 4);
  SupernodalLu lu;
  ASSERT_TRUE(lu.refactorize(A));
  set_first_diagonal_block(lu.structure(), 0.0, A);
  EXPECT_FALSE(lu.refactorize(A));
  EXPECT_NE(lu.status().find("zero pivot"), std::string::npos) << lu.status();
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x;
  EXPECT_FALSE(lu.solve(b, x));
  auto automatic = make_linear_solver(SolverKind::kAuto);
  ASSERT_TRUE(automatic->refactorize(A)) << automatic->status();
  EXPECT_EQ(automatic->name(), "klu");
  ASSERT_TRUE(automatic->solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
  // A large multiplier (a tiny diagonal block against the rows below it) is refused too.
  set_first_diagonal_block(lu.structure(), 1e-6, A);
  EXPECT_FALSE(lu.refactorize(A));
  EXPECT_GT(lu.largest_multiplier(), SupernodalLu::kMultiplierLimit);
  // The matrix as it was: `auto` returns to the supernodal LU after its pause.
  const SparseMatrix good = membrane_matrix(10, 9, 11, 4);
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(automatic->refactorize(good));
    ASSERT_TRUE(automatic->solve(b, x));
    EXPECT_LE(relative_residual(good, x, b), 1e-13);
  }
  EXPECT_EQ(automatic->name(), "supernodal-lu");
}

// The top separators of a larger grid are supernodes wider than the triangular solves take
// in one block (160 columns, dense_kernels.hpp): solved by column blocks, as accurate.
TEST(SupernodalLu, WideSupernodesAreSolvedByColumnBlocks) {
  const SparseMatrix A = membrane_matrix(70, 70, 17);
  SupernodalLu lu;
  ASSERT_TRUE(lu.refactorize(A)) << lu.status();
  EXPECT_GT(lu.structure().widest, 160);
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x, y;
  ASSERT_TRUE(lu.solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
  auto umfpack = make_linear_solver(SolverKind::kUmfpack);
  ASSERT_TRUE(umfpack->refactorize(A) && umfpack->solve(b, y));
  EXPECT_LE((x - y).norm(), 1e-11 * y.norm());
}

// A NaN in the matrix is refused, wherever it lands: never a factor that solves to NaNs.
TEST(SupernodalLu, NotANumberIsRefused) {
  const SparseMatrix good = membrane_matrix(9, 8, 19);
  for (const int column : {0, 40, static_cast<int>(good.cols()) - 1}) {
    SparseMatrix A = good;
    A.valuePtr()[A.outerIndexPtr()[column]] = std::numeric_limits<double>::quiet_NaN();
    SupernodalLu lu;
    Eigen::VectorXd x;
    // Refused by the factorisation itself (its pivot or multiplier tests), not left to the
    // solve's check of its answer.
    EXPECT_FALSE(lu.refactorize(A)) << "column " << column;
    EXPECT_FALSE(lu.status().empty()) << "column " << column;
    EXPECT_FALSE(lu.solve(rhs(A.rows()), x)) << "column " << column;
  }
}

// Above 6,000 equations the factorisation with full pivoting is UMFPACK's.
TEST(SupernodalLu, AutoFallsBackToUmfpackAboveKlusSize) {
  SparseMatrix A = membrane_matrix(46, 45, 13);
  ASSERT_GT(A.rows(), 6000);
  SupernodalLu lu;
  ASSERT_TRUE(lu.refactorize(A));
  set_first_diagonal_block(lu.structure(), 0.0, A);
  auto automatic = make_linear_solver(SolverKind::kAuto);
  ASSERT_TRUE(automatic->refactorize(A)) << automatic->status();
  EXPECT_EQ(automatic->name(), "umfpack");
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x;
  ASSERT_TRUE(automatic->solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
}

TEST(SupernodalLu, SingularMatrixIsReportedNeverSolved) {
  SparseMatrix A = membrane_matrix(8, 8, 2);
  // Column 17 a copy of column 16 (the same node, so the same pattern): rank deficient.
  for (SparseMatrix::InnerIterator a(A, 16), c(A, 17); a && c; ++a, ++c) c.valueRef() = a.value();
  SupernodalLu lu;
  EXPECT_FALSE(lu.refactorize(A));
  EXPECT_FALSE(lu.status().empty());
  Eigen::VectorXd x;
  EXPECT_FALSE(lu.solve(rhs(A.rows()), x));
  auto automatic = make_linear_solver(SolverKind::kAuto);
  const bool factorised = automatic->refactorize(A);
  Eigen::VectorXd y;
  // KLU may meet a pivot of round-off size instead of zero; then the answer must not be
  // silently finite garbage passed as a solution with a NaN inside.
  if (factorised && automatic->solve(rhs(A.rows()), y)) {
    EXPECT_TRUE(y.allFinite());
  }
  // A zero column: every back-end reports it.
  for (SparseMatrix::InnerIterator c(A, 17); c; ++c) c.valueRef() = 0.0;
  EXPECT_FALSE(lu.refactorize(A));
  EXPECT_FALSE(automatic->refactorize(A));
}

}  // namespace
}  // namespace velum
