// The symmetry test that picks LDLᵀ or LU: structural and numerical, without a position map.
#include <gtest/gtest.h>
#include <omp.h>

#include <limits>
#include <vector>

#include "membrane_grid.hpp"
#include "solve/symmetry.hpp"

namespace velum {
namespace {

SparseMatrix from(int n, const std::vector<Eigen::Triplet<double>>& t) {
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// A symmetric 5 x 5 with a full first row and column, a band and one missing diagonal.
std::vector<Eigen::Triplet<double>> symmetric_entries() {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < 5; ++i)
    if (i != 3) t.emplace_back(i, i, 4.0 + i);
  for (int i = 1; i < 5; ++i) t.emplace_back(0, i, -1.0 * i), t.emplace_back(i, 0, -1.0 * i);
  t.emplace_back(2, 3, 0.5), t.emplace_back(3, 2, 0.5);
  t.emplace_back(1, 4, 2.0), t.emplace_back(4, 1, 2.0);
  return t;
}

TEST(SymmetryCheck, AcceptsSymmetricWithAMissingDiagonal) {
  const SparseMatrix A = from(5, symmetric_entries());
  SymmetryCheck c;
  EXPECT_TRUE(c.map(A));
  EXPECT_TRUE(c.symmetric(A));
}

TEST(SymmetryCheck, RejectsUnequalValuesAboveRoundOff) {
  auto t = symmetric_entries();
  t.emplace_back(4, 1, 1e-6);  // (4,1) = 2 + 1e-6, (1,4) = 2
  SparseMatrix A = from(5, t);
  SymmetryCheck c;
  ASSERT_TRUE(c.map(A));
  EXPECT_FALSE(c.symmetric(A));
  A.coeffRef(1, 4) += 1e-6;  // the same pattern made symmetric again
  EXPECT_TRUE(c.symmetric(A));
  A.coeffRef(1, 4) += 1e-14;  // round-off of the assembly is still symmetric
  EXPECT_TRUE(c.symmetric(A));
}

TEST(SymmetryCheck, RejectsAMissingTransposeOnEitherSide) {
  for (const auto& [i, j] : {std::pair{3, 1}, std::pair{1, 3}}) {
    auto t = symmetric_entries();
    t.emplace_back(i, j, 1.0);
    const SparseMatrix A = from(5, t);
    SymmetryCheck c;
    EXPECT_FALSE(c.map(A)) << i << "," << j;
    EXPECT_FALSE(c.symmetric(A));
  }
}

// symmetric() walks the lower entries only and meets the upper ones as their partners: an upper
// or a lower entry without its transpose is still found when the pattern changed after map().
TEST(SymmetryCheck, TheLowerWalkFindsAnUnpairedEntryOnEitherSide) {
  SymmetryCheck c;
  ASSERT_TRUE(c.map(from(5, symmetric_entries())));
  for (const auto& [i, j] : {std::pair{3, 1}, std::pair{1, 3}, std::pair{4, 2}, std::pair{2, 4}}) {
    auto t = symmetric_entries();
    t.emplace_back(i, j, 1.0);
    EXPECT_FALSE(c.symmetric(from(5, t))) << i << "," << j;
  }
}

// symmetric() stops at the first pair that decides: the same answer as the full walk, whether
// the deciding pair comes first or last, and with an infinite entry.
TEST(SymmetryCheck, EarlyStopGivesTheFullWalksAnswer) {
  for (const auto& [i, j] : {std::pair{1, 0}, std::pair{4, 1}}) {
    for (const double d : {1e-12, 1e-8, 1.0}) {
      auto t = symmetric_entries();
      t.emplace_back(i, j, d);
      const SparseMatrix A = from(5, t);
      SymmetryCheck c;
      ASSERT_TRUE(c.map(A));
      EXPECT_EQ(c.symmetric(A), c.asymmetry(A) <= SymmetryCheck::kTolerance) << i << j << d;
      EXPECT_EQ(c.symmetric(A), d < 1e-9) << i << "," << j << " " << d;
    }
  }
  auto t = symmetric_entries();
  t.emplace_back(2, 2, std::numeric_limits<double>::infinity());
  const SparseMatrix A = from(5, t);
  SymmetryCheck c;
  ASSERT_TRUE(c.map(A));
  EXPECT_EQ(c.symmetric(A), c.asymmetry(A) <= SymmetryCheck::kTolerance);
}

// Above a million entries the check runs on the threads through a map of partner positions
// made by map(): the same answers, a zero matrix symmetric.
TEST(SymmetryCheck, LargeMatricesOnTwoThreads) {
  const MembraneGrid grid(200, 70, 0);
  std::vector<Eigen::Triplet<double>> t;
  grid.for_each_coupling([&](int r, int c) { t.emplace_back(r, c, 1.0 + (r + c) % 7); });
  for (int i = 0; i < grid.n; ++i) t.emplace_back(i, i, 100.0);
  SparseMatrix A = from(grid.n, t);
  ASSERT_GE(A.nonZeros(), 1'000'000);
  const int before = omp_get_max_threads();
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    SparseMatrix B = A;
    SymmetryCheck c;
    ASSERT_TRUE(c.map(B));
    EXPECT_TRUE(c.symmetric(B));
    B.coeffRef(5000, 5003) += 1e-6;  // one pair unequal above round-off
    EXPECT_FALSE(c.symmetric(B));
    B.coeffRef(5003, 5000) += 1e-6;
    EXPECT_TRUE(c.symmetric(B));
    B.coeffRef(grid.n - 1, grid.n - 4) = -7.0;  // in the last row
    EXPECT_FALSE(c.symmetric(B));
    // The entries changed were in the pattern (coeffRef inserts otherwise): the mapped check,
    // made for this pattern, is what answered.
    ASSERT_EQ(B.nonZeros(), A.nonZeros());
    B.coeffs().setZero();
    EXPECT_TRUE(c.symmetric(B));
  }
  omp_set_num_threads(before);
}

}  // namespace
}  // namespace velum
