// Couplings beyond the elements (Assembler::set_couplings): the pattern gains the node pairs'
// 3 x 3 blocks both ways, the element entries still land where they did (the tangent's values
// unchanged), a new set changes the pattern's revision and the same set does not.
#include <gtest/gtest.h>

#include "square_membrane.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/assembly/dof_map.hpp"

namespace velum {
namespace {

TEST(AssemblerCouplings, AddNodeBlocksAndKeepTheElementEntries) {
  const int n = 6;
  auto model = clamped_square(n, 0.05);
  const DofMap dofs(*model);
  Assembler assembler(*model, dofs);
  NodePositions x = model->X, F;
  x(2, 2 * (n + 1) + 3) += 0.01;  // a state with a tangent other than the reference's
  SparseMatrix K0 = assembler.make_matrix();
  assembler.internal(x, F, &K0);
  const Eigen::Index before = assembler.nonzeros();
  EXPECT_EQ(assembler.pattern_revision(), 0);
  // Two inner nodes far apart (no shared element), and a pair already coupled by elements.
  const int a = 1 * (n + 1) + 1, b = 4 * (n + 1) + 4, c = a + 1;
  ASSERT_GE(dofs.equation(a, 0), 0);
  ASSERT_GE(dofs.equation(b, 0), 0);
  assembler.set_couplings({{b, a}, {a, c}});
  const long revision = assembler.pattern_revision();
  EXPECT_NE(revision, 0);
  EXPECT_EQ(assembler.nonzeros(), before + 2 * 9);  // the far pair's two blocks only
  SparseMatrix K1 = assembler.make_matrix();
  EXPECT_EQ(K1.nonZeros(), assembler.nonzeros());
  assembler.internal(x, F, &K1);
  // Every entry of the elements' tangent where it was, the couplings' blocks stored and zero.
  EXPECT_EQ((MatX(K1) - MatX(K0)).cwiseAbs().maxCoeff(), 0.0);
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) {
      const int i = dofs.equation(a, r), j = dofs.equation(b, s);
      bool stored_ij = false, stored_ji = false;
      for (SparseMatrix::InnerIterator it(K1, j); it; ++it) stored_ij |= it.row() == i;
      for (SparseMatrix::InnerIterator it(K1, i); it; ++it) stored_ji |= it.row() == j;
      EXPECT_TRUE(stored_ij && stored_ji) << r << " " << s;
    }
  // The same set (another order): nothing rebuilt; none: back to the elements' pattern.
  assembler.set_couplings({{c, a}, {a, b}});
  EXPECT_EQ(assembler.pattern_revision(), revision);
  assembler.set_couplings({});
  EXPECT_NE(assembler.pattern_revision(), revision);
  EXPECT_EQ(assembler.nonzeros(), before);
}

}  // namespace
}  // namespace velum
