// The supernodal Cholesky (src/solve/supernodal_cholesky.hpp) on symmetric matrices built like
// membrane stiffnesses: three equations per node of a quad mesh, every equation of a node
// coupled with every equation of the nodes that share an element with it, some equations
// removed (constrained components). Positive definite ones against a dense LLᵀ and CHOLMOD;
// an indefinite one refused and solved by `auto` through MUMPS's LDLᵀ with its inertia; a
// singular one refused.
#include <gtest/gtest.h>

#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <limits>
#include <random>
#include <vector>

#include "membrane_grid.hpp"
#include "solve/supernodal_cholesky.hpp"
#include "square_membrane.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// An nx x ny grid of nodes, quad4 elements, 3 equations per node (every `drop`-th equation
// removed when drop > 0), symmetric random values in [-1, 1] off the diagonal, each diagonal
// entry its row's off-diagonal sum plus `margin`: diagonally dominant, so positive definite
// for margin > 0.
SparseMatrix spd_membrane_matrix(int nx, int ny, unsigned seed, int drop = 0, double margin = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const MembraneGrid grid(nx, ny, drop);
  const int n = grid.n;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> row_sum(n, 0.0);
  grid.for_each_coupling([&](int r, int c) {
    if (r > c) return;  // each pair once, mirrored
    const double v = u(rng);
    t.emplace_back(r, c, v);
    t.emplace_back(c, r, v);
    row_sum[r] += std::abs(v);
    row_sum[c] += std::abs(v);
  });
  for (int c = 0; c < n; ++c) t.emplace_back(c, c, row_sum[c] + margin);
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

TEST(SupernodalCholesky, SolvesMembraneMatricesLikeDenseLltAndCholmod) {
  for (const int drop : {0, 7}) {
    const SparseMatrix A = spd_membrane_matrix(14, 11, 3, drop);
    SupernodalCholesky chol;
    ASSERT_TRUE(chol.refactorize(A)) << chol.status();
    EXPECT_EQ(chol.negative_pivots(), 0);
    Eigen::VectorXd x, y;
    const Eigen::VectorXd b = rhs(A.rows());
    ASSERT_TRUE(chol.solve(b, x));
    EXPECT_LE(relative_residual(A, x, b), 1e-13);
    auto cholmod = make_linear_solver(SolverKind::kCholmod);
    ASSERT_TRUE(cholmod->refactorize(A) && cholmod->solve(b, y));
    EXPECT_LE((x - y).norm(), 1e-11 * y.norm());
    // Row-major: libgmsh, linked into this test program, has its own Eigen instantiations.
    const Eigen::VectorXd dense = RowMajorMatrix(A).llt().solve(b);
    EXPECT_LE((x - dense).norm(), 1e-11 * dense.norm());
    // Supernodes at least node-sized where no equation was removed; L's panels only.
    const SupernodalStructure& st = chol.structure();
    EXPECT_LT(st.supernodes(), A.rows() / 3 + 1);
    EXPECT_TRUE(st.u_panel.empty());
    EXPECT_GT(st.flops, 0.0);
  }
}

TEST(SupernodalCholesky, RefactorisesNewValuesOnTheSamePattern) {
  const SparseMatrix A = spd_membrane_matrix(12, 9, 5, 5);
  const SparseMatrix C = spd_membrane_matrix(12, 9, 6, 5, 0.1);
  ASSERT_EQ(A.nonZeros(), C.nonZeros());
  SupernodalCholesky chol;
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x;
  ASSERT_TRUE(chol.refactorize(A));
  ASSERT_TRUE(chol.solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
  ASSERT_TRUE(chol.refactorize(C));
  ASSERT_TRUE(chol.solve(b, x));
  EXPECT_LE(relative_residual(C, x, b), 1e-13);
  EXPECT_EQ(chol.analyses(), 1);
}

// The factorisation reads A's lower triangle only (and keeps only that copy): A with every
// entry above the diagonal changed (within the diagonal blocks too, which the panels hold
// whole) factorises and solves to the same bits, in double and in mixed precision, where the
// refinement's residuals are A's lower triangle's too.
TEST(SupernodalCholesky, ReadsTheLowerTriangleOnly) {
  const SparseMatrix A = spd_membrane_matrix(16, 13, 8, 5);
  SparseMatrix B = A;
  for (int j = 0; j < B.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(B, j); it; ++it)
      if (it.row() < j) it.valueRef() *= 1.5;
  const Eigen::VectorXd b = rhs(A.rows());
  for (const auto precision :
       {SupernodalCholesky::Precision::kDouble, SupernodalCholesky::Precision::kMixed}) {
    SupernodalCholesky a({}, SupernodalCholesky::kSplitFlops, precision);
    SupernodalCholesky c({}, SupernodalCholesky::kSplitFlops, precision);
    Eigen::VectorXd xa, xc;
    ASSERT_TRUE(a.refactorize(A) && a.solve(b, xa));
    ASSERT_TRUE(c.refactorize(B) && c.solve(b, xc));
    EXPECT_EQ(c.mixed(), precision == SupernodalCholesky::Precision::kMixed);
    EXPECT_TRUE(xa == xc);
    EXPECT_LE(relative_residual(A, xa, b), 1e-13);
    EXPECT_GT(relative_residual(B, xa, b), 1e-3);  // B itself is another matrix
  }
}

// A shift between two eigenvalues makes the matrix indefinite with a known inertia: the
// Cholesky refuses it, `auto` factorises it with MUMPS's LDLᵀ and reports the negative
// eigenvalues; for a positive definite matrix it returns to the Cholesky after its pause.
TEST(SupernodalCholesky, RefusesAnIndefiniteMatrixAndAutoGivesItsInertia) {
  const SparseMatrix good = spd_membrane_matrix(10, 9, 11, 4);
  const Eigen::VectorXd lambda =
      Eigen::SelfAdjointEigenSolver<RowMajorMatrix>(RowMajorMatrix(good)).eigenvalues();
  const int negative = 7;
  const double shift = 0.5 * (lambda[negative - 1] + lambda[negative]);
  SparseMatrix A = good;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (it.row() == j) it.valueRef() -= shift;
  SupernodalCholesky chol;
  EXPECT_FALSE(chol.refactorize(A));
  EXPECT_NE(chol.status().find("not positive definite"), std::string::npos) << chol.status();
  EXPECT_EQ(chol.negative_pivots(), -1);
  const Eigen::VectorXd b = rhs(A.rows());
  Eigen::VectorXd x;
  EXPECT_FALSE(chol.solve(b, x));
  auto automatic = make_linear_solver(SolverKind::kAuto);
  ASSERT_TRUE(automatic->refactorize(good));
  if (!have_mumps()) GTEST_SKIP() << "the Cholesky's fallback in `auto` is MUMPS's LDLᵀ";
  EXPECT_EQ(automatic->name(), "supernodal-cholesky");
  EXPECT_EQ(automatic->negative_pivots(), 0);
  ASSERT_TRUE(automatic->refactorize(A)) << automatic->status();
  EXPECT_EQ(automatic->name(), "mumps");
  EXPECT_EQ(automatic->negative_pivots(), negative);
  ASSERT_TRUE(automatic->solve(b, x));
  EXPECT_LE(relative_residual(A, x, b), 1e-13);
  // Back-off: the next factorisation goes to MUMPS directly, the one after to the Cholesky.
  for (const char* expected : {"mumps", "supernodal-cholesky", "supernodal-cholesky"}) {
    ASSERT_TRUE(automatic->refactorize(good));
    EXPECT_EQ(automatic->name(), expected);
    EXPECT_EQ(automatic->negative_pivots(), 0);
    ASSERT_TRUE(automatic->solve(b, x));
    EXPECT_LE(relative_residual(good, x, b), 1e-13);
  }
}

TEST(SupernodalCholesky, SingularMatrixIsReportedNeverSolved) {
  SparseMatrix A = spd_membrane_matrix(8, 8, 2);
  // Equation 17 a copy of equation 16 (the same node, so the same pattern): positive
  // semi-definite, rank deficient.
  RowMajorMatrix M(A);
  M.row(17) = M.row(16);
  M.col(17) = M.col(16);
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) it.valueRef() = M(it.row(), j);
  SupernodalCholesky chol;
  EXPECT_FALSE(chol.refactorize(A));
  EXPECT_FALSE(chol.status().empty());
  Eigen::VectorXd x;
  EXPECT_FALSE(chol.solve(rhs(A.rows()), x));
  // A zero column and row.
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (it.row() == 17 || j == 17) it.valueRef() = 0.0;
  EXPECT_FALSE(chol.refactorize(A));
  EXPECT_NE(chol.status().find("not positive definite"), std::string::npos) << chol.status();
}

// The tree-split factorisation (forced here by a threshold of 0 flops): on one thread and on
// two the same factor and the same solution to the bit, run after run; the same solution as
// the sequence of supernodes to round-off; a refusal on either side of the split.
class ThreadCount {  // omp_set_num_threads for one scope
 public:
  explicit ThreadCount(int n) : before_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~ThreadCount() { omp_set_num_threads(before_); }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;

 private:
  int before_;
};

TEST(SupernodalCholesky, TreeSplitOnTwoThreadsMatchesOneThreadToTheBit) {
  for (const int drop : {0, 7}) {
    const SparseMatrix A = spd_membrane_matrix(40, 33, 9, drop);
    const Eigen::VectorXd b = rhs(A.rows());
    SupernodalCholesky sequence({}, 1e300);
    ASSERT_TRUE(sequence.refactorize(A)) << sequence.status();
    EXPECT_FALSE(sequence.splits());
    Eigen::VectorXd reference;
    ASSERT_TRUE(sequence.solve(b, reference));
    EXPECT_LE(relative_residual(A, reference, b), 1e-13);

    std::vector<Eigen::VectorXd> solutions;
    for (const int threads : {1, 2, 2, 1, 2}) {
      const ThreadCount scope(threads);
      SupernodalCholesky split({}, 0.0);
      ASSERT_TRUE(split.refactorize(A)) << split.status();
      ASSERT_TRUE(split.splits());
      const TreeSplit& ts = split.split();
      EXPECT_FALSE(ts.members[0].empty());
      EXPECT_FALSE(ts.members[1].empty());
      EXPECT_FALSE(ts.top.empty());
      EXPECT_EQ(ts.members[0].size() + ts.members[1].size() + ts.top.size(),
                static_cast<std::size_t>(split.structure().supernodes()));
      // Balanced to within a third of the subtrees' work.
      EXPECT_LT(std::abs(ts.flops[0] - ts.flops[1]), (ts.flops[0] + ts.flops[1]) / 3);
      Eigen::VectorXd x;
      ASSERT_TRUE(split.solve(b, x));
      EXPECT_LE(relative_residual(A, x, b), 1e-13);
      EXPECT_LE((x - reference).norm(), 1e-12 * reference.norm());
      EXPECT_EQ(split.pivot_ratio(), sequence.pivot_ratio());
      // A second factorisation of the same values in the same object: the same bits.
      ASSERT_TRUE(split.refactorize(A));
      Eigen::VectorXd again;
      ASSERT_TRUE(split.solve(b, again));
      EXPECT_TRUE(again == x);
      solutions.push_back(x);
    }
    for (const Eigen::VectorXd& x : solutions) EXPECT_TRUE(x == solutions.front());
  }
}

TEST(SupernodalCholesky, TreeSplitRefusesAnIndefiniteMatrix) {
  const SparseMatrix good = spd_membrane_matrix(30, 30, 4, 5);
  // A negative diagonal entry (e_jᵀ A e_j < 0): one in the middle, then one every 97 equations
  // (on both sides of the split).
  for (const int every : {0, 97}) {
    SparseMatrix A = good;
    for (int j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        if (it.row() == j && (every ? j % every == 0 : j == A.rows() / 2)) it.valueRef() = -1.0;
    for (const int threads : {1, 2}) {
      const ThreadCount scope(threads);
      SupernodalCholesky split({}, 0.0);
      EXPECT_FALSE(split.refactorize(A));
      EXPECT_NE(split.status().find("not positive definite"), std::string::npos) << split.status();
      Eigen::VectorXd x;
      EXPECT_FALSE(split.solve(rhs(A.rows()), x));
      ASSERT_TRUE(split.refactorize(good)) << split.status();
      ASSERT_TRUE(split.solve(rhs(A.rows()), x));
      EXPECT_LE(relative_residual(good, x, rhs(A.rows())), 1e-13);
    }
  }
}

// Trees the split must also take: a forest (two unconnected grids, no common separator) and a
// chain (a tridiagonal matrix: every supernode the parent of the one before, so no two subtrees
// are independent below the root).
TEST(SupernodalCholesky, TreeSplitOfAForestAndOfAChain) {
  const SparseMatrix grid = spd_membrane_matrix(24, 20, 13, 6);
  const int g = static_cast<int>(grid.rows());
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < g; ++j)
    for (SparseMatrix::InnerIterator it(grid, j); it; ++it) {
      t.emplace_back(it.row(), j, it.value());
      t.emplace_back(g + it.row(), g + j, it.value() * 2.0);
    }
  SparseMatrix forest(2 * g, 2 * g);
  forest.setFromTriplets(t.begin(), t.end());
  t.clear();
  const int n = 3000;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    if (i > 0) t.emplace_back(i, i - 1, -1.0), t.emplace_back(i - 1, i, -1.0);
  }
  SparseMatrix chain(n, n);
  chain.setFromTriplets(t.begin(), t.end());
  for (const SparseMatrix* A : {&forest, &chain}) {
    const Eigen::VectorXd b = rhs(A->rows());
    Eigen::VectorXd first;
    for (const int threads : {1, 2}) {
      const ThreadCount scope(threads);
      SupernodalCholesky split({}, 0.0);
      ASSERT_TRUE(split.refactorize(*A)) << split.status();
      EXPECT_TRUE(split.splits());
      Eigen::VectorXd x;
      ASSERT_TRUE(split.solve(b, x));
      EXPECT_LE(relative_residual(*A, x, b), 1e-13);
      if (threads == 1)
        first = x;
      else
        EXPECT_TRUE(x == first);
    }
  }
}

// Mixed precision (float panels, refinement in double).
using Precision = SupernodalCholesky::Precision;

// LAPACK's DSPOSV test, which the refinement stops at: ‖b − A x‖∞ / (‖A‖∞ ‖x‖∞).
double backward_error(const SparseMatrix& A, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  double norm = 0;
  for (int j = 0; j < A.outerSize(); ++j) norm = std::max(norm, A.col(j).cwiseAbs().sum());
  return (b - A * x).lpNorm<Eigen::Infinity>() / (norm * x.lpNorm<Eigen::Infinity>());
}

// A mixed solve as accurate as the double one: LAPACK's test met, the same solution to the
// condition number's measure, the float factor kept and each solve refined.
void expect_double_accuracy(const SparseMatrix& A, double agreement) {
  const Eigen::VectorXd b = rhs(A.rows());
  SupernodalCholesky exact, mixed({}, SupernodalCholesky::kSplitFlops, Precision::kMixed);
  ASSERT_TRUE(exact.refactorize(A)) << exact.status();
  ASSERT_TRUE(mixed.refactorize(A)) << mixed.status();
  EXPECT_TRUE(mixed.float_factor());
  EXPECT_FALSE(exact.float_factor());
  Eigen::VectorXd x, y;
  ASSERT_TRUE(exact.solve(b, y));
  ASSERT_TRUE(mixed.solve(b, x));
  const double target = std::sqrt(double(A.rows())) * SupernodalCholesky::kRoundoff;
  EXPECT_LE(backward_error(A, x, b), target);
  EXPECT_LE(mixed.mixed_counts().last_backward_error, target);
  EXPECT_LE((x - y).norm(), agreement * y.norm());
  const SupernodalCholesky::MixedCounts& c = mixed.mixed_counts();
  EXPECT_EQ(c.float_factorizations, 1);
  EXPECT_EQ(c.refined_solves, 1);  // float's rounding alone is far above the target
  EXPECT_GE(c.float_solves, 2);
  EXPECT_LE(c.float_solves, 4);
  EXPECT_EQ(c.double_fallbacks, 0);
  EXPECT_TRUE(mixed.float_factor());
  // A second solve with the same factor, and a zero right-hand side.
  ASSERT_TRUE(mixed.solve(2.0 * b, x));
  EXPECT_LE((x - 2.0 * y).norm(), 2 * agreement * y.norm());
  ASSERT_TRUE(mixed.solve(Eigen::VectorXd::Zero(A.rows()), x));
  EXPECT_EQ(x.norm(), 0.0);
}

TEST(MixedCholesky, RefinesRandomMembraneMatricesToDoubleAccuracy) {
  for (const int drop : {0, 7})
    expect_double_accuracy(spd_membrane_matrix(30, 27, 21, drop), 1e-13);
}

// The pressurised square's K + M (3 equations per free node, quad4, 40 x 40 elements) and the
// stress-free clamped dome's stiffness, ill-conditioned enough that float's factor needs more
// corrections (or none of it stands: then the double factor solves).
// The pressurised square's K + M at rest (n x n quad4 elements).
SparseMatrix square_stiffness_and_mass(int n) {
  auto model = pressurised_square(n);
  MechanicalSystem sys(*model);
  VecX u = VecX::Zero(sys.size()), v = u, a = u, r;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, 1.0, 0.0, 1.0, r, &J);
  return J;
}

TEST(MixedCholesky, RefinesTheSquareMembraneToDoubleAccuracy) {
  expect_double_accuracy(square_stiffness_and_mass(40), 1e-12);
  // Supernodes wide enough that OpenBLAS's float kernels take their updates where they are
  // used (the AVX-512 run of these tests, tests/unit/CMakeLists.txt): 93 columns here.
  const SparseMatrix A = square_stiffness_and_mass(64);
  SupernodalCholesky analysed;
  ASSERT_TRUE(analysed.analyze(A));
  const SupernodalStructure& st = analysed.structure();
  int widest_updating = 0;
  for (int s = 0; s < st.supernodes(); ++s)
    if (st.below(s) > 0) widest_updating = std::max(widest_updating, st.width(s));
  EXPECT_GE(widest_updating, SupernodalCholesky::kBlasWidth);
  expect_double_accuracy(A, 1e-12);
}

// solve_within: the refinement stops once ‖b − A x‖₂ is within the residual asked for, never
// above it, and with none asked (0) goes on to LAPACK's test as solve does (the pressurised
// square's K + M, which takes more than one float solve to reach it).
TEST(MixedCholesky, SolveWithinStopsTheRefinementAtTheResidualAsked) {
  const SparseMatrix A = square_stiffness_and_mass(40);
  const Eigen::VectorXd b = rhs(A.rows());
  SupernodalCholesky mixed({}, SupernodalCholesky::kSplitFlops, Precision::kMixed);
  ASSERT_TRUE(mixed.refactorize(A)) << mixed.status();
  Eigen::VectorXd exact, x;
  ASSERT_TRUE(mixed.solve(b, exact));
  const long full = mixed.mixed_counts().float_solves;
  ASSERT_GE(full, 2);
  for (const double relative : {1e-1, 1e-4, 1e-8}) {
    const long before = mixed.mixed_counts().float_solves;
    ASSERT_TRUE(mixed.solve_within(b, x, relative * b.norm()));
    const long solves = mixed.mixed_counts().float_solves - before;
    EXPECT_LE((b - A * x).norm(), relative * b.norm()) << relative;
    EXPECT_GE(solves, 1);
    EXPECT_LE(solves, full);
    if (relative == 1e-1) {
      EXPECT_EQ(solves, 1);  // float's own solve is within a tenth
      EXPECT_LT(solves, full);
    }
    EXPECT_TRUE(mixed.float_factor());
  }
  const long before = mixed.mixed_counts().float_solves;
  ASSERT_TRUE(mixed.solve_within(b, x, 0.0));
  EXPECT_EQ(mixed.mixed_counts().float_solves - before, full);
  EXPECT_TRUE(x == exact);
  // With double panels the solve is the double solve whatever the residual asked.
  SupernodalCholesky plain;
  ASSERT_TRUE(plain.refactorize(A));
  Eigen::VectorXd y, z;
  ASSERT_TRUE(plain.solve(b, y));
  ASSERT_TRUE(plain.solve_within(b, z, 1e-1 * b.norm()));
  EXPECT_TRUE(y == z);
}

// one_pass_accuracy: unknown (NaN) until a checked solve measures the float solve's relative
// residual, which is then that of the float solve alone; solve_within with an infinite residual
// is that one float solve, unchecked (the same x, no refinement); the double factor's is 0.
TEST(MixedCholesky, OnePassIsTheFloatSolveAsMeasured) {
  const SparseMatrix A = square_stiffness_and_mass(40);
  const Eigen::VectorXd b = rhs(A.rows());
  SupernodalCholesky mixed({}, SupernodalCholesky::kSplitFlops, Precision::kMixed);
  ASSERT_TRUE(mixed.refactorize(A)) << mixed.status();
  EXPECT_TRUE(std::isnan(mixed.one_pass_accuracy()));
  const double infinite = std::numeric_limits<double>::infinity();
  Eigen::VectorXd one, exact;
  long before = mixed.mixed_counts().float_solves;
  ASSERT_TRUE(mixed.solve_within(b, one, infinite));
  EXPECT_EQ(mixed.mixed_counts().float_solves - before, 1);
  EXPECT_TRUE(std::isnan(mixed.one_pass_accuracy()));  // nothing measured
  before = mixed.mixed_counts().float_solves;
  ASSERT_TRUE(mixed.solve(b, exact));
  EXPECT_GE(mixed.mixed_counts().float_solves - before, 2);  // refined
  const double measured = (b - A * one).norm() / b.norm();
  EXPECT_NEAR(mixed.one_pass_accuracy(), measured, 1e-6 * measured);
  EXPECT_GT(measured, 1e-10);  // float's, not double's
  EXPECT_LT(measured, 1e-2);
  Eigen::VectorXd again;
  ASSERT_TRUE(mixed.solve_within(b, again, infinite));
  EXPECT_TRUE(again == one);
  SupernodalCholesky plain;
  ASSERT_TRUE(plain.refactorize(A));
  EXPECT_EQ(plain.one_pass_accuracy(), 0.0);
}

// A membrane graph's weighted Laplacian (weights in [0.5, 1.5], positive semi-definite with
// the constant vector in its null space) shifted by δ: cond ≈ 100 / δ. Rounded to float, its
// smallest eigenvalue moves by about 1e-7 either way: from δ = 1e-2 the float factor's
// corrections converge; towards δ = 1e-8 they stall (the float matrix's lowest eigenvalue
// several times δ's) or the float factorisation meets a pivot that is not positive, and the
// double factor solves, always to double's accuracy.
TEST(MixedCholesky, FallsBackToDoubleWhereRefinementCannotConverge) {
  const MembraneGrid grid(20, 18, 0);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> weight(0.5, 1.5);
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> degree(grid.n, 0.0);
  grid.for_each_coupling([&](int row, int col) {
    if (row >= col) return;
    const double w = weight(rng);
    t.emplace_back(row, col, -w);
    t.emplace_back(col, row, -w);
    degree[row] += w;
    degree[col] += w;
  });
  const std::size_t off_diagonal = t.size();
  long refused = 0, fallbacks = 0, refined = 0;
  for (const double delta : {1e-2, 1e-5, 1e-6, 3e-7, 1e-7, 5e-8, 1e-8}) {
    t.resize(off_diagonal);
    for (int c = 0; c < grid.n; ++c) t.emplace_back(c, c, degree[c] + delta);
    SparseMatrix A(grid.n, grid.n);
    A.setFromTriplets(t.begin(), t.end());
    const Eigen::VectorXd b = rhs(A.rows());
    SupernodalCholesky exact, mixed({}, SupernodalCholesky::kSplitFlops, Precision::kMixed);
    ASSERT_TRUE(exact.refactorize(A)) << exact.status();
    ASSERT_TRUE(mixed.refactorize(A)) << mixed.status();
    Eigen::VectorXd x, y;
    ASSERT_TRUE(exact.solve(b, y));
    ASSERT_TRUE(mixed.solve(b, x));
    const double target = std::sqrt(double(A.rows())) * SupernodalCholesky::kRoundoff;
    EXPECT_LE(backward_error(A, x, b), target) << delta;
    const SupernodalCholesky::MixedCounts& c = mixed.mixed_counts();
    refused += c.float_refusals;
    fallbacks += c.double_fallbacks;
    refined += c.double_fallbacks == 0 && c.float_refusals == 0;
    if (c.double_fallbacks + c.float_refusals > 0) {
      // The double factor's own solution, to the bit.
      EXPECT_FALSE(mixed.float_factor());
      EXPECT_TRUE(x == y) << delta;
    } else {
      EXPECT_LE((x - y).norm(), 1e-13 / delta * y.norm()) << delta;
    }
    if (delta == 1e-2) {
      EXPECT_EQ(c.double_fallbacks + c.float_refusals, 0);
    }
  }
  // After a fallback the next factorisation is in double, the one after in float again; kAuto
  // keeps a matrix this small in double.
  SupernodalCholesky mixed({}, SupernodalCholesky::kSplitFlops, Precision::kMixed);
  const std::array<double, 3> shifts = {3e-7, 1e-2, 1e-2};
  const std::array<bool, 3> in_float = {false, false, true};  // after each one's first solve
  for (int k = 0; k < 3; ++k) {
    t.resize(off_diagonal);
    for (int c = 0; c < grid.n; ++c) t.emplace_back(c, c, degree[c] + shifts[k]);
    SparseMatrix A(grid.n, grid.n);
    A.setFromTriplets(t.begin(), t.end());
    ASSERT_TRUE(mixed.refactorize(A)) << mixed.status();
    EXPECT_TRUE(mixed.mixed());
    Eigen::VectorXd x;
    ASSERT_TRUE(mixed.solve(rhs(A.rows()), x));
    EXPECT_LE(backward_error(A, x, rhs(A.rows())),
              std::sqrt(double(A.rows())) * SupernodalCholesky::kRoundoff);
    EXPECT_EQ(mixed.float_factor(), in_float[k]) << k;
    SupernodalCholesky automatic({}, SupernodalCholesky::kSplitFlops, Precision::kAuto);
    ASSERT_TRUE(automatic.refactorize(A));
    EXPECT_FALSE(automatic.mixed());
    EXPECT_FALSE(automatic.float_factor());
  }
  EXPECT_EQ(mixed.mixed_counts().double_fallbacks, 1);
  EXPECT_EQ(mixed.mixed_counts().float_factorizations, 2);
  // As measured: refined at 1e-2 to 1e-6, 1e-7 and 5e-8 (in 2 to 10 corrections), stalled at
  // 3e-7, refused at 1e-8 (which of the borderline shifts stalls depends on the float factor's
  // round-off: 5e-8 stalled too before the narrow update products).
  EXPECT_GE(refined, 3);
  EXPECT_GE(fallbacks, 1);
  EXPECT_GE(refused, 1);
}

// A grid large enough that some updates are 64 columns wide or wider with 256 rows below or
// more, in the subtrees and in the top (without OpenBLAS's AVX-512 kernels they go to
// dense_products.cpp's packed products, the top's by column blocks): double and mixed, the
// same solution to the bit on one thread and on two, and the backward error at round-off.
TEST(SupernodalCholesky, WideUpdatesOnTwoThreadsMatchOneThreadToTheBit) {
  const SparseMatrix A = spd_membrane_matrix(110, 100, 5);
  const Eigen::VectorXd b = rhs(A.rows());
  for (const Precision precision : {Precision::kDouble, Precision::kMixed}) {
    std::vector<Eigen::VectorXd> solutions;
    for (const int threads : {1, 2, 1, 2}) {
      const ThreadCount scope(threads);
      SupernodalCholesky split({}, 0.0, precision);
      ASSERT_TRUE(split.refactorize(A)) << split.status();
      ASSERT_TRUE(split.splits());
      if (solutions.empty()) {  // the shapes this test is for: wide, tall updates on both sides
        const SupernodalStructure& st = split.structure();
        const auto wide_and_tall = [&](int s) {
          return st.width(s) >= SupernodalCholesky::kBlasWidth &&
                 st.below(s) >= SupernodalCholesky::kPackedRows;
        };
        const TreeSplit& ts = split.split();
        EXPECT_TRUE(std::any_of(ts.members[0].begin(), ts.members[0].end(), wide_and_tall));
        EXPECT_TRUE(std::any_of(ts.top.begin(), ts.top.end(), wide_and_tall));
      }
      Eigen::VectorXd x;
      ASSERT_TRUE(split.solve(b, x));
      EXPECT_LE(backward_error(A, x, b),
                std::sqrt(double(A.rows())) * SupernodalCholesky::kRoundoff);
      solutions.push_back(x);
    }
    for (const Eigen::VectorXd& x : solutions) EXPECT_TRUE(x == solutions.front());
  }
}

// Above the split threshold the float factor and the refinement are the same, to the bit, on one
// thread and on two.
TEST(MixedCholesky, TreeSplitOnTwoThreadsMatchesOneThreadToTheBit) {
  const SparseMatrix A = spd_membrane_matrix(40, 33, 9, 7);
  const Eigen::VectorXd b = rhs(A.rows());
  std::vector<Eigen::VectorXd> solutions;
  for (const int threads : {1, 2, 1, 2}) {
    const ThreadCount scope(threads);
    SupernodalCholesky split({}, 0.0, Precision::kMixed);
    ASSERT_TRUE(split.refactorize(A)) << split.status();
    ASSERT_TRUE(split.splits());
    EXPECT_TRUE(split.float_factor());
    Eigen::VectorXd x;
    ASSERT_TRUE(split.solve(b, x));
    EXPECT_LE(backward_error(A, x, b), std::sqrt(double(A.rows())) * SupernodalCholesky::kRoundoff);
    solutions.push_back(x);
  }
  for (const Eigen::VectorXd& x : solutions) EXPECT_TRUE(x == solutions.front());
}

}  // namespace
}  // namespace velum
