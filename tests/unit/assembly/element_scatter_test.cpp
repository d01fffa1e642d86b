#include "velum/assembly/element_scatter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "square_membrane.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/assembly/dof_map.hpp"

namespace velum {
namespace {

// On the clamped square (edge nodes without equations) with the nodes of one row held in x
// only (two equations each: their elements keep every position), every entry of every
// element lands where a search of the pattern puts it, through position() and through add();
// entries of eliminated equations nowhere.
TEST(ElementScatter, PutsEveryEntryWhereThePatternHasIt) {
  const int n = 9;
  auto model = clamped_square(n);
  std::vector<int> row;
  for (int i = 1; i < n; ++i) row.push_back(4 * (n + 1) + i);
  model->fixed.push_back({row, {true, false, false}});
  const DofMap dofs(*model);
  const Assembler assembler(*model, dofs);
  const SparseMatrix A = assembler.make_matrix();
  const ElementBlock& b = *model->blocks[0];
  std::vector<int> elements;  // every other element, as a process's share might be
  for (int e = 0; e < b.size(); e += 2) elements.push_back(e);
  const ElementScatter scatter(b, elements, dofs, A);
  const int nd = b.dofs_per_element();
  int compact = 0;
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const auto nodes = b.nodes(elements[k]);
    std::vector<int> eq(static_cast<std::size_t>(nd));
    for (int a = 0; a < b.nodes_per_element(); ++a)
      for (int c = 0; c < 3; ++c) eq[3 * a + c] = dofs.equation(nodes[a], c);
    compact += scatter.compact(static_cast<int>(k)) ? 1 : 0;
    std::vector<double> Ke(static_cast<std::size_t>(nd * nd)), values(A.nonZeros(), 0.0),
        expected(A.nonZeros(), 0.0);
    for (int j = 0; j < nd; ++j)
      for (int i = 0; i < nd; ++i) {
        Ke[j * nd + i] = 1 + i + nd * j;
        const int* inner = A.innerIndexPtr();
        const int* begin = inner + (eq[j] >= 0 ? A.outerIndexPtr()[eq[j]] : 0);
        const int* end = inner + (eq[j] >= 0 ? A.outerIndexPtr()[eq[j] + 1] : 0);
        const int* at = std::lower_bound(begin, end, eq[i]);
        const int want =
            eq[i] >= 0 && eq[j] >= 0 && at != end && *at == eq[i] ? int(at - inner) : -1;
        ASSERT_EQ(scatter.position(static_cast<int>(k), i, j), want)
            << "element " << elements[k] << " entry (" << i << ", " << j << ")";
        if (want >= 0) expected[want] += Ke[j * nd + i];
      }
    scatter.add(static_cast<int>(k), Ke.data(), values.data());
    EXPECT_EQ(values, expected) << "element " << elements[k];
  }
  // Both forms are exercised: the row's elements keep every position, the rest are compact.
  EXPECT_GT(compact, 0);
  EXPECT_LT(compact, static_cast<int>(elements.size()));
}

}  // namespace
}  // namespace velum
