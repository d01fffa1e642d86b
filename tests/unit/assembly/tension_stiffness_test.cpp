// The borrowed tension's stiffness (Assembler::add_tension_stiffness, and its diagonal alone,
// tension_stiffness_diagonal: what MechanicalSystem::stiffen_stress_free scales it by),
// added element by element with no matrix of its own.
#include <gtest/gtest.h>

#include "square_membrane.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/assembly/dof_map.hpp"

namespace velum {
namespace {

TEST(TensionStiffness, TheDiagonalIsTheMatrixsAndTheRowsOfFreeNodesSumToZero) {
  const int n = 5;
  auto model = clamped_square(n, 0.05);  // a dome: the rim's equations are gone
  const DofMap dofs(*model);
  Assembler assembler(*model, dofs);
  NodePositions x = model->X, F;
  SparseMatrix K = assembler.make_matrix();
  assembler.internal(x, F, &K);  // added to a tangent, as a stress-free start does
  const VecX before = K.diagonal();
  constexpr double kScale = 2.5;
  assembler.add_tension_stiffness(K, kScale);
  const VecX d = assembler.tension_stiffness_diagonal();
  ASSERT_EQ(d.size(), K.rows());
  EXPECT_GT(d.minCoeff(), 0.0);  // every free equation is stiffened
  const VecX added = K.diagonal() - before;
  // (To the round-off of the tangent's entries, which are far larger: E t against 1.)
  EXPECT_LE((added - kScale * d).cwiseAbs().maxCoeff(), 1e-15 * before.cwiseAbs().maxCoeff());
  EXPECT_GT(1e-15 * before.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(1e-15 * before.cwiseAbs().maxCoeff(), 1e-3 * kScale * d.minCoeff());
  // T is symmetric, the same on each component, and a uniform tension's stiffness has no
  // resistance to a rigid translation: the rows of a node whose neighbours are all free sum to
  // zero (their columns all stored).
  SparseMatrix Kt = assembler.make_matrix();
  assembler.add_tension_stiffness(Kt, 1.0);
  EXPECT_LE((MatX(Kt) - MatX(Kt).transpose()).cwiseAbs().maxCoeff(), 1e-14 * d.maxCoeff());
  const int centre = (n / 2) * (n + 1) + n / 2;
  for (int c = 0; c < 3; ++c) {
    const int q = dofs.equation(centre, c);
    ASSERT_GE(q, 0);
    EXPECT_NEAR(MatX(Kt).row(q).sum(), 0.0, 1e-12 * d.maxCoeff());
    EXPECT_DOUBLE_EQ(Kt.coeff(q, q), d[q]);
  }
}

}  // namespace
}  // namespace velum
