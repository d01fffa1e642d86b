// Sliding cable block: the consistent tangent against central differences of the forces, the
// forces against central differences of the energy (taut, truss in compression), one force
// along the chain, and the lumped mass along it.
#include <gtest/gtest.h>

#include "velum/model/element_block.hpp"

namespace velum {
namespace {

struct Chain {
  NodePositions X{3, 4}, x{3, 4};
  Chain() {
    X << 0, 1, 2, 3.5, 0, 0.5, 0.2, 0, 0, 0, 0.3, 0;
    x = X;
    x.col(1) += Vec3(0.05, -0.3, 0.1);
    x.col(2) += Vec3(-0.1, 0.2, -0.05);
    x.col(3) += Vec3(0.4, 0.1, 0.02);
  }
};

std::unique_ptr<ElementBlock> make(const NodePositions& X, const CableLaw& law) {
  BlockSetupReport report;
  return make_sliding_cable_block("rope", 4, {0, 1, 2, 3}, X, law, 7.0, 0.01, report);
}

void check_tangent(const ElementBlock& block, const NodePositions& x0) {
  const ElementBlock* b = &block;
  const int nd = 12;
  const std::vector<int> e{0};
  Eigen::VectorXd r(nd), rp(nd), rm(nd);
  Eigen::MatrixXd K(nd, nd);
  b->internal(e, x0, r.data(), K.data());
  const double h = 1e-6;
  double scale = K.cwiseAbs().maxCoeff();
  for (int d = 0; d < nd; ++d) {
    NodePositions xp = x0, xm = x0;
    xp(d % 3, d / 3) += h;
    xm(d % 3, d / 3) -= h;
    b->internal(e, xp, rp.data(), nullptr);
    b->internal(e, xm, rm.data(), nullptr);
    const Eigen::VectorXd col = (rp - rm) / (2 * h);
    EXPECT_LT((col - K.col(d)).cwiseAbs().maxCoeff(), 1e-6 * scale) << "dof " << d;
    const double Up = b->strain_energy(e, xp), Um = b->strain_energy(e, xm);
    EXPECT_NEAR((Up - Um) / (2 * h), r[d], 1e-6 * r.cwiseAbs().maxCoeff()) << "dof " << d;
  }
}

void check_tangent(const CableLaw& law, const NodePositions& x0, const NodePositions& X) {
  check_tangent(*make(X, law), x0);
}

TEST(SlidingCable, TangentMatchesCentralDifferencesTaut) {
  Chain c;
  check_tangent({2.0e9, false, 0.0}, c.x, c.X);
}

TEST(SlidingCable, TangentMatchesCentralDifferencesTrussInCompression) {
  Chain c;
  NodePositions x = c.X;
  x.col(3) -= Vec3(0.6, 0, 0);  // the chain shorter than its reference
  x.col(1) += Vec3(0.02, 0.01, 0.03);
  check_tangent({2.0e9, true, 0.0}, x, c.X);
}

// Form finding's chain (on_reference with a stabilizer): the prestress one force along the
// chain, a stabilizer per segment; stretched, and with segments shorter than their reference
// (the stabilizer then pushes).
TEST(SlidingCable, FormFindingTangentMatchesCentralDifferences) {
  Chain c;
  const auto ff = make(c.X, {2.0e9, false, 3.0e7})->on_reference(c.X, 1.0);
  check_tangent(*ff, c.x);
  NodePositions x = c.X;
  x.col(1) += Vec3(0.3, 0.02, 0.03);  // segment 1 longer, segment 2 shorter
  check_tangent(*ff, x);
  // On its own reference it carries the prestress, one force: A S0 at both ends.
  Eigen::VectorXd r(12);
  ff->internal(std::vector<int>{0}, c.X, r.data(), nullptr);
  EXPECT_NEAR(r.segment<3>(0).norm(), 0.01 * 3.0e7, 1e-9 * 3.0e5);
  EXPECT_NEAR(r.segment<3>(9).norm(), 0.01 * 3.0e7, 1e-9 * 3.0e5);
  EXPECT_NEAR(ff->output(0, c.X).cable_force, 0.01 * 3.0e7, 1e-9 * 3.0e5);
}

TEST(SlidingCable, OneForceAlongTheChainAndBalanced) {
  Chain c;
  auto b = make(c.X, {2.0e9, false, 0.0});
  Eigen::VectorXd r(12);
  b->internal(std::vector<int>{0}, c.x, r.data(), nullptr);
  const double T = b->output(0, c.x).cable_force;
  EXPECT_GT(T, 0);
  EXPECT_NEAR(r.segment<3>(0).norm(), T, 1e-9 * T);  // the end forces carry T
  EXPECT_NEAR(r.segment<3>(9).norm(), T, 1e-9 * T);
  Vec3 sum = Vec3::Zero();
  for (int n = 0; n < 4; ++n) sum += r.segment<3>(3 * n);
  EXPECT_LT(sum.norm(), 1e-9 * T);
}

TEST(SlidingCable, SlackChainCarriesNothing) {
  Chain c;
  NodePositions x = c.X;
  x.col(3) -= Vec3(0.5, 0, 0);
  auto b = make(c.X, {2.0e9, false, 0.0});
  Eigen::VectorXd r(12);
  b->internal(std::vector<int>{0}, x, r.data(), nullptr);
  EXPECT_EQ(r.norm(), 0.0);
}

TEST(SlidingCable, MassRowSumsAreHalfSegmentsAtEachNode) {
  Chain c;
  auto b = make(c.X, {2.0e9, false, 0.0});
  Eigen::MatrixXd M(4, 4);
  b->mass(0, M.data());
  const double total = 7.0 * 0.01 * b->measure(0);
  EXPECT_NEAR(M.sum(), total, 1e-12 * total);
  const double l0 = (c.X.col(1) - c.X.col(0)).norm();
  EXPECT_NEAR(M.row(0).sum(), 0.5 * 7.0 * 0.01 * l0, 1e-12);
}

TEST(SlidingCable, OneSegmentIsRefused) {
  NodePositions X(3, 2);
  X << 0, 1, 0, 0, 0, 0;
  BlockSetupReport report;
  EXPECT_THROW(make_sliding_cable_block("rope", 2, {0, 1}, X, {1.0, false, 0.0}, 1, 1, report),
               std::invalid_argument);
}

}  // namespace
}  // namespace velum
