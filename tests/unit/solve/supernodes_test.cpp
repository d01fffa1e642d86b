// The supernodal structure found on the graph of a matrix's nodes (runs of equations with one
// pattern) is the one found on the graph of its equations: same order, supernodes, rows,
// panels, flops and update targets, for nodes of 3, 2 and 1 equations (eliminated components),
// for orderings that keep the nodes together or split them, and for a pattern whose blocks
// are not all dense (then the nodes are not used).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "solve/ordering.hpp"
#include "solve/supernodes.hpp"

namespace velum {
namespace {

// An m x m grid of nodes, each coupled to its right, upper and (at random) diagonal
// neighbours, with 3 equations per node except some with 2 or 1; every block dense.
SparseMatrix random_node_grid(int m, std::mt19937& rng, std::vector<int>& node_first) {
  std::uniform_int_distribution<int> size_of(0, 9), coin(0, 1);
  node_first.assign(1, 0);
  for (int a = 0; a < m * m; ++a)
    node_first.push_back(node_first.back() + (size_of(rng) == 0 ? 1 + coin(rng) : 3));
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int a, int b) {
    for (int i = node_first[a]; i < node_first[a + 1]; ++i)
      for (int j = node_first[b]; j < node_first[b + 1]; ++j) {
        t.emplace_back(i, j, 1.0);
        if (a != b) t.emplace_back(j, i, 1.0);
      }
  };
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) {
      const int a = x + m * y;
      add(a, a);
      if (x + 1 < m) add(a, a + 1);
      if (y + 1 < m) add(a, a + m);
      if (x + 1 < m && y + 1 < m && coin(rng)) add(a, a + m + 1);
    }
  const int n = node_first.back();
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

void expect_same(const SupernodalStructure& a, const SupernodalStructure& b) {
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.below_begin, b.below_begin);
  EXPECT_EQ(a.rows, b.rows);
  EXPECT_EQ(a.l_panel, b.l_panel);
  EXPECT_EQ(a.u_panel, b.u_panel);
  EXPECT_EQ(a.entry, b.entry);
  EXPECT_EQ(a.load_begin, b.load_begin);
  ASSERT_EQ(a.loads.size(), b.loads.size());
  for (std::size_t k = 0; k < a.loads.size(); ++k) {
    EXPECT_EQ(a.loads[k].a, b.loads[k].a);
    EXPECT_EQ(a.loads[k].at, b.loads[k].at);
  }
  EXPECT_EQ(a.target_begin, b.target_begin);
  ASSERT_EQ(a.targets.size(), b.targets.size());
  for (std::size_t k = 0; k < a.targets.size(); ++k) {
    EXPECT_EQ(a.targets[k].supernode, b.targets[k].supernode);
    EXPECT_EQ(a.targets[k].begin, b.targets[k].begin);
    EXPECT_EQ(a.targets[k].end, b.targets[k].end);
    EXPECT_EQ(a.targets[k].rel, b.targets[k].rel);
  }
  EXPECT_EQ(a.relative, b.relative);
  EXPECT_EQ(a.flops, b.flops);
  EXPECT_EQ(a.values, b.values);
}

void expect_nodes_give_the_same(const SparseMatrix& A, const std::vector<int>& position) {
  for (const Factor f : {Factor::kCholesky, Factor::kLu}) {
    const SupernodalStructure by_nodes = analyse_supernodes(A, position, {}, f, true);
    const SupernodalStructure by_equations = analyse_supernodes(A, position, {}, f, false);
    EXPECT_GT(by_nodes.supernodes(), 1);
    expect_same(by_nodes, by_equations);
  }
}

TEST(Supernodes, NodeGraphGivesTheEquationGraphsStructure) {
  std::mt19937 rng(21);
  for (int m : {3, 12, 25}) {
    std::vector<int> node_first;
    const SparseMatrix A = random_node_grid(m, rng, node_first);
    const int n = static_cast<int>(A.rows());
    SCOPED_TRACE(testing::Message() << "grid " << m << ", " << n << " equations");
    {
      SCOPED_TRACE("nested dissection");
      expect_nodes_give_the_same(A, nested_dissection(A));
    }
    {
      SCOPED_TRACE("natural order");
      expect_nodes_give_the_same(A, {});
    }
    {
      SCOPED_TRACE("random order of the nodes, their equations together");
      std::vector<int> nodes(node_first.size() - 1), position(n);
      std::iota(nodes.begin(), nodes.end(), 0);
      std::shuffle(nodes.begin(), nodes.end(), rng);
      int next = 0;
      for (const int a : nodes)
        for (int j = node_first[a]; j < node_first[a + 1]; ++j) position[j] = next++;
      expect_nodes_give_the_same(A, position);
    }
    {
      SCOPED_TRACE("random order of the equations: nodes split");
      std::vector<int> position(n);
      std::iota(position.begin(), position.end(), 0);
      std::shuffle(position.begin(), position.end(), rng);
      expect_nodes_give_the_same(A, position);
    }
  }
}

TEST(Supernodes, BlocksNotAllDenseFallBackToTheEquations) {
  std::mt19937 rng(7);
  std::vector<int> node_first;
  const SparseMatrix full = random_node_grid(10, rng, node_first);
  // One entry of an off-diagonal block dropped from every column of its node (A stays
  // without it, Aᵀ holds it): the node's columns keep one pattern, its block is not dense.
  const int a = 11;  // a node in the grid's interior, and its right neighbour's first column
  ASSERT_GT(node_first[a + 1] - node_first[a], 0);
  const int dropped = node_first[a + 1];
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < full.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(full, j); it; ++it)
      if (!(it.row() == dropped && j >= node_first[a] && j < node_first[a + 1]))
        t.emplace_back(static_cast<int>(it.row()), j, 1.0);
  SparseMatrix A(full.rows(), full.cols());
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  ASSERT_EQ(A.nonZeros(), full.nonZeros() - (node_first[a + 1] - node_first[a]));
  expect_nodes_give_the_same(A, nested_dissection(A));
  expect_nodes_give_the_same(A, {});
}

}  // namespace
}  // namespace velum
