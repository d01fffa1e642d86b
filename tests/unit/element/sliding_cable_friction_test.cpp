// Sliding cable with friction at its interior nodes: the capstan ratio e^(μθ) at every node
// that slips, sticking below it, the slips committed at accepted states only, no friction
// the same forces as the one-force chain, reefing and the cut, and the consistent tangent
// against central differences while nodes slip and while they stick.
#include <gtest/gtest.h>

#include <cmath>

#include "velum/element/sliding_cable_friction.hpp"
#include "velum/model/element_block.hpp"

namespace velum {
namespace {

constexpr double kArea = 1e-4;
const CableLaw kSteel{2.0e9, false, 0.0};

// A zig-zag chain of five nodes: three interior nodes with wrap angles of about 50 degrees.
NodePositions zigzag() {
  NodePositions X(3, 5);
  X << 0, 1, 2, 3, 4,     //
      0, 0.5, 0, 0.6, 0,  //
      0, 0, 0.2, 0, 0;
  return X;
}

std::unique_ptr<ElementBlock> make(const NodePositions& X, double mu,
                                   SlidingCableSection section = {}) {
  BlockSetupReport report;
  section.friction = mu;
  std::vector<int> conn(static_cast<size_t>(X.cols()));
  for (int i = 0; i < static_cast<int>(X.cols()); ++i) conn[static_cast<size_t>(i)] = i;
  return make_sliding_cable_block("rope", static_cast<int>(X.cols()), conn, X, kSteel, 7.0, kArea,
                                  report, section);
}

// Each segment's force from the forces at the nodes (the end force is the first's).
std::vector<double> segment_forces(const ElementBlock& b, const NodePositions& x) {
  const int k = b.nodes_per_element();
  Eigen::VectorXd r(3 * k);
  b.internal(std::vector<int>{0}, x, r.data(), nullptr);
  std::vector<double> T;
  Vec3 carried = Vec3::Zero();  // the force the chain carries past node j, from node 0
  for (int j = 0; j + 1 < k; ++j) {
    carried += r.segment<3>(3 * j);
    T.push_back(carried.norm());
  }
  return T;
}

double wrap(const NodePositions& x, int i) {
  const Vec3 a = (x.col(i) - x.col(i - 1)).normalized(), b = (x.col(i + 1) - x.col(i)).normalized();
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

void check_tangent_by_differences(const ElementBlock& b, const NodePositions& x0) {
  const int nd = b.dofs_per_element();
  const std::vector<int> e{0};
  Eigen::VectorXd r(nd), rp(nd), rm(nd);
  Eigen::MatrixXd K(nd, nd);
  b.internal(e, x0, r.data(), K.data());
  const double h = 1e-7, scale = K.cwiseAbs().maxCoeff();
  for (int d = 0; d < nd; ++d) {
    NodePositions xp = x0, xm = x0;
    xp(d % 3, d / 3) += h;
    xm(d % 3, d / 3) -= h;
    b.internal(e, xp, rp.data(), nullptr);
    b.internal(e, xm, rm.data(), nullptr);
    const Eigen::VectorXd col = (rp - rm) / (2 * h);
    EXPECT_LT((col - K.col(d)).cwiseAbs().maxCoeff(), 1e-6 * scale) << "dof " << d;
  }
}

TEST(SlidingCableFriction, PulledEndSlipsEveryNodeInTheCapstanRatio) {
  const NodePositions X = zigzag();
  const double mu = 0.3;
  auto b = make(X, mu);
  NodePositions x = X;
  x.col(4) += Vec3(0.004, 0, 0);
  const auto T = segment_forces(*b, x);
  for (int i = 1; i <= 3; ++i) {
    EXPECT_GT(b->sliding()->slip(0, i, x), 0) << "node " << i;
    EXPECT_NEAR(T[i] / T[i - 1], std::exp(mu * wrap(x, i)), 1e-9) << "node " << i;
  }
}

TEST(SlidingCableFriction, WithoutFrictionTheOneForceChain) {
  const NodePositions X = zigzag();
  NodePositions x = X;
  x.col(4) += Vec3(0.02, 0.001, -0.002);
  x.col(2) += Vec3(0.01, 0.01, 0);
  auto b = make(X, 0.0);
  const int nd = b->dofs_per_element();
  Eigen::VectorXd r0(nd), r1(nd);
  b->internal(std::vector<int>{0}, x, r0.data(), nullptr);
  // The friction solve with μ = 0: the segments stretched alike, the same forces.
  sliding_cable::FrictionWork w;
  std::vector<double> L0, committed(3, 0.0), slips(3), free(3);
  for (int j = 0; j < 4; ++j) L0.push_back((X.col(j + 1) - X.col(j)).norm());
  const sliding_cable::FrictionChain c{L0, committed, 0.0, 1.0};
  sliding_cable::friction_force_tangent(x, c, kArea, kSteel,
                                        sliding_cable::VectorMap(r1.data(), nd), nullptr, slips, w);
  ASSERT_GT(r0.norm(), 0);
  EXPECT_LT((r1 - r0).norm(), 1e-9 * r0.norm());
  sliding_cable::frictionless_slips(x, L0, free);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(slips[i], free[i], 1e-12);
    EXPECT_NEAR(b->sliding()->slip(0, i + 1, x), free[i], 1e-15);
  }
}

TEST(SlidingCableFriction, SticksBelowTheRatioUntilCommitted) {
  const NodePositions X = zigzag();
  auto b = make(X, 0.3);
  NodePositions pulled = X;
  pulled.col(4) += Vec3(0.004, 0, 0);
  const double s3 = b->sliding()->slip(0, 3, pulled);
  b->commit_history(pulled);
  // Let go a little: the forces fall but stay within the ratio: nothing slips back.
  NodePositions eased = X;
  eased.col(4) += Vec3(0.0036, 0, 0);
  EXPECT_DOUBLE_EQ(b->sliding()->slip(0, 3, eased), s3);
  const auto T = segment_forces(*b, eased);
  EXPECT_LT(T[3] / T[2], std::exp(0.3 * wrap(eased, 3)));
  EXPECT_GT(T[3] / T[2], std::exp(-0.3 * wrap(eased, 3)));
  // Without the commit the slips return from the reference state: history, not the last call.
  auto fresh = make(X, 0.3);
  EXPECT_NE(fresh->sliding()->slip(0, 3, eased), s3);
  // Saved and restored, the committed slips come back.
  std::vector<double> saved;
  b->save_history(saved);
  ASSERT_EQ(saved.size(), 3u);
  EXPECT_EQ(fresh->restore_history(saved, 0), 3u);
  EXPECT_DOUBLE_EQ(fresh->sliding()->slip(0, 3, eased), s3);
}

TEST(SlidingCableFriction, TangentMatchesCentralDifferencesSlipping) {
  const NodePositions X = zigzag();
  auto b = make(X, 0.3);
  NodePositions x = X;
  x.col(4) += Vec3(0.004, 0.001, -0.002);
  x.col(2) += Vec3(0.001, 0.003, 0.001);
  check_tangent_by_differences(*b, x);
}

TEST(SlidingCableFriction, TangentMatchesCentralDifferencesMixed) {
  const NodePositions X = zigzag();
  auto b = make(X, 0.3);
  NodePositions pulled = X;
  pulled.col(4) += Vec3(0.004, 0, 0);
  b->commit_history(pulled);
  // The far end eased (its node sticks), the first end pulled (its nodes slip backward).
  NodePositions x = pulled;
  x.col(4) -= Vec3(0.0004, 0, 0);
  x.col(0) -= Vec3(0.002, 0.0005, 0);
  check_tangent_by_differences(*b, x);
  const double s3 = b->sliding()->slip(0, 3, pulled);
  EXPECT_DOUBLE_EQ(b->sliding()->slip(0, 3, x), s3);
  EXPECT_LT(b->sliding()->slip(0, 1, x), b->sliding()->slip(0, 1, pulled));
}

TEST(SlidingCableFriction, TangentMatchesCentralDifferencesSticking) {
  const NodePositions X = zigzag();
  auto b = make(X, 0.3);
  // Stretched nearly alike: the forces well within the ratio at every node.
  NodePositions x = 1.001 * X;
  x.col(2) += Vec3(0.0002, -0.0001, 0.0001);
  x.col(3) += Vec3(-0.0001, 0.0001, 0);
  check_tangent_by_differences(*b, x);
  for (int i = 1; i <= 3; ++i) EXPECT_EQ(b->sliding()->slip(0, i, x), 0) << "node " << i;
}

TEST(SlidingCableFriction, ReefedLineIsShorterAndCutLineCarriesNothing) {
  const NodePositions X = zigzag();
  SlidingCableSection section;
  TimeFunction f;
  f.kind = TimeFunction::Kind::kTable;
  f.points = {{0, 1.0}, {1, 0.99}};
  section.reefing = f;
  section.cut_time = 2;
  for (double mu : {0.0, 0.3}) {
    auto b = make(X, mu, section);
    b->set_time(0);
    EXPECT_EQ(b->output(0, X).cable_force, 0);
    b->set_time(1);  // the material 1% shorter: the same strain everywhere, no slip
    const double T = b->output(0, X).cable_force;
    const double lam = 1 / 0.99;
    EXPECT_NEAR(T, kArea * kSteel.E * 0.5 * (lam * lam - 1) * lam, 1e-9 * T) << "mu " << mu;
    if (mu > 0) check_tangent_by_differences(*b, X);
    b->set_time(2);
    EXPECT_EQ(b->output(0, X).cable_force, 0);
    Eigen::VectorXd r(15);
    b->internal(std::vector<int>{0}, X, r.data(), nullptr);
    EXPECT_EQ(r.norm(), 0);
  }
}

TEST(SlidingCableFriction, NegativeFrictionIsRefused) {
  const NodePositions X = zigzag();
  EXPECT_THROW(make(X, -0.1), std::invalid_argument);
}

}  // namespace
}  // namespace velum
