// The nested dissection ordering handed to MUMPS: a permutation that keeps each node's
// equations together and cuts the fill of a membrane-like matrix well below a band ordering.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <vector>

#include "solve/ordering.hpp"

namespace velum {
namespace {

// An m x m grid of nodes with three equations each, numbered node by node along the rows
// (a band of width 3m): the grid Laplacian coupled through an SPD 3 x 3 block.
SparseMatrix grid_of_nodes(int m) {
  const double block[3][3] = {{4, 1, 0}, {1, 4, 1}, {0, 1, 4}};
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int a, int b, double w) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t.emplace_back(3 * a + i, 3 * b + j, w * block[i][j]);
  };
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) {
      const int a = x + m * y;
      add(a, a, 4.5);
      if (x + 1 < m) add(a, a + 1, -1), add(a + 1, a, -1);
      if (y + 1 < m) add(a, a + m, -1), add(a + m, a, -1);
    }
  SparseMatrix A(3 * m * m, 3 * m * m);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

Eigen::Index cholesky_entries(const SparseMatrix& A) {
  Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(A);
  EXPECT_EQ(llt.info(), Eigen::Success);
  return llt.matrixL().nestedExpression().nonZeros();
}

TEST(Ordering, NestedDissectionKeepsNodesTogetherAndCutsTheFill) {
  const int m = 40;
  const SparseMatrix A = grid_of_nodes(m);
  const std::vector<int> position = nested_dissection(A);
  ASSERT_EQ(position.size(), static_cast<size_t>(A.rows()));
  std::vector<int> order(A.rows(), -1);
  for (int i = 0; i < A.rows(); ++i) {
    ASSERT_GE(position[i], 0);
    ASSERT_LT(position[i], A.rows());
    ASSERT_EQ(order[position[i]], -1) << "position " << position[i] << " given twice";
    order[position[i]] = i;
  }
  for (int node = 0; node < m * m; ++node)  // a node's equations in consecutive positions
    for (int c = 1; c < 3; ++c) EXPECT_EQ(position[3 * node + c], position[3 * node] + c);

  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(A.rows());
  for (int i = 0; i < A.rows(); ++i) P.indices()[i] = position[i];
  SparseMatrix B;
  B = A.selfadjointView<Eigen::Lower>().twistedBy(P);
  const Eigen::Index band = cholesky_entries(A), dissected = cholesky_entries(B);
  EXPECT_LT(dissected, band / 2) << "band " << band << ", nested dissection " << dissected;
}

}  // namespace
}  // namespace velum
