// The sheet-law interface (SheetLawBase behind SheetLaw): its tangent equals central finite
// differences of its stress, and its stress those of its energy, for the linear anisotropic
// law with a prestress and with wrinkling; a toy law that is not affine (stress quadratic in
// E), written against the interface alone, passes the membrane patch test through the kernels
// and through a block, with a consistent element tangent; an affine law other than the linear
// one takes the blocks' fast path with the same bits; a block keeps the history of a law that
// has one; the handle clones, and wraps other laws in a prestress and a tension field.
#include <gtest/gtest.h>

#include <numbers>

#include "../support.hpp"
#include "velum/element/membrane.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/model/element_block.hpp"

namespace velum {
namespace {

/// W = ½ EᵀQE + (k/3)(a·E)³: S = QE + k (a·E)² a, C = Q + 2k (a·E) a aᵀ. Not affine.
class QuadraticLaw final : public SheetLawBase {
 public:
  QuadraticLaw(const Mat3& Q, double k, const Vec3& a) : Q_(Q), k_(k), a_(a) {}
  const std::string& name() const override { return name_; }
  void evaluate(const Vec3& E, std::span<const double>, SheetResponse& out) const override {
    const double s = a_.dot(E);
    out.S = Q_ * E + k_ * s * s * a_;
    out.C = Q_ + 2 * k_ * s * a_ * a_.transpose();
  }
  double energy(const Vec3& E, std::span<const double>) const override {
    const double s = a_.dot(E);
    return 0.5 * E.dot(Q_ * E) + k_ / 3 * s * s * s;
  }
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return Q_; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<QuadraticLaw>(*this);
  }

 private:
  std::string name_ = "quadratic";
  Mat3 Q_;
  double k_;
  Vec3 a_;
};

/// S = Q E + S0 written against the interface: an affine law that is not LinearSheetLaw.
class AffineLaw final : public SheetLawBase {
 public:
  AffineLaw(const Mat3& Q, const Vec3& S0) : Q_(Q), S0_(S0) {}
  const std::string& name() const override { return name_; }
  void evaluate(const Vec3& E, std::span<const double>, SheetResponse& out) const override {
    out.S = Q_ * E + S0_;
    out.C = Q_;
  }
  double energy(const Vec3& E, std::span<const double>) const override {
    return 0.5 * E.dot(Q_ * E) + S0_.dot(E);
  }
  bool affine() const override { return true; }
  const Mat3& reference_stiffness() const override { return Q_; }
  Vec3 prestress() const override { return S0_; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<AffineLaw>(*this);
  }

 private:
  std::string name_ = "affine";
  Mat3 Q_;
  Vec3 S0_;
};

/// A law with one double of history per point (its stress ignores it).
class HistoryLaw final : public SheetLawBase {
 public:
  const std::string& name() const override { return name_; }
  void evaluate(const Vec3& E, std::span<const double>, SheetResponse& out) const override {
    out.S = E;
    out.C = Mat3::Identity();
  }
  double energy(const Vec3& E, std::span<const double>) const override {
    return 0.5 * E.squaredNorm();
  }
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return I_; }
  int state_size() const override { return 1; }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<HistoryLaw>(*this);
  }

 private:
  std::string name_ = "history";
  Mat3 I_ = Mat3::Identity();
};

PlaneStressLaw anisotropic() {
  AnisotropicConstants c;
  c.E1 = 2000.0, c.E2 = 1000.0, c.nu12 = 0.3, c.G12 = 400.0, c.eta1 = 0.25, c.eta2 = -0.15;
  return PlaneStressLaw::anisotropic("aniso", c);
}

QuadraticLaw quadratic_law() {
  return {anisotropic().Q(), 4e4, Vec3(1.0, 0.6, 0.3)};
}

/// Central differences of the stress (C) and of the energy (S) through the interface; false
/// when the law's state changes within ±h (a kink of the tension field).
bool finite_differences(const SheetLawBase& law, const Vec3& E, double h, Mat3& C, Vec3& S) {
  SheetResponse at, p, m;
  law.evaluate(E, {}, at);
  for (int j = 0; j < 3; ++j) {
    Vec3 Ep = E, Em = E;
    Ep[j] += h;
    Em[j] -= h;
    law.evaluate(Ep, {}, p);
    law.evaluate(Em, {}, m);
    if (p.state != at.state || m.state != at.state) return false;
    C.col(j) = (p.S - m.S) / (2 * h);
    S[j] = (law.energy(Ep, {}) - law.energy(Em, {})) / (2 * h);
  }
  return true;
}

void expect_derivatives(const SheetLaw& law, const std::string& label, int want_wrinkled) {
  test::Random rnd(4040);
  const double h = 1e-6;
  int checked = 0, wrinkled = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Vec3 E = rnd.vec3(-0.02, 0.03);
    Mat3 C_fd;
    Vec3 S_fd;
    if (!finite_differences(law.base(), E, h, C_fd, S_fd)) continue;
    SheetResponse r;
    law.evaluate(E, r);
    const double scale = law.reference_stiffness().cwiseAbs().maxCoeff();
    EXPECT_LT((r.C - C_fd).cwiseAbs().maxCoeff(), 1e-6 * scale) << label << " " << E.transpose();
    EXPECT_LT((r.S - S_fd).cwiseAbs().maxCoeff(), 1e-6 * scale * std::max(1.0, E.norm()))
        << label << " " << E.transpose();
    ++checked;
    if (r.state == WrinkleState::kWrinkled) ++wrinkled;
  }
  EXPECT_GT(checked, 40) << label;
  EXPECT_GE(wrinkled, want_wrinkled) << label;
}

TEST(SheetLawInterface, TangentAndStressAreTheDerivativesOfStressAndEnergy) {
  const Vec3 S0(30, 12, 4);
  expect_derivatives(SheetLaw(anisotropic()).with_prestress(S0), "anisotropic, prestress", 0);
  // κ = 0: the residual stiffness κ Q is added to the tangent only, not the derivative of
  // the stress (tension_field_test checks the tangent is the derivative plus κ Q).
  expect_derivatives(SheetLaw(anisotropic()).with_prestress(S0).with_wrinkling(0.0),
                     "anisotropic, prestress, wrinkling", 5);
  expect_derivatives(SheetLaw(quadratic_law()), "quadratic", 0);
}

TEST(SheetLawInterface, AffineLinearLawReportsItsParts) {
  const Vec3 S0(30, 12, 4);
  const SheetLaw law = SheetLaw(anisotropic()).with_prestress(S0);
  EXPECT_TRUE(law.affine());
  EXPECT_EQ(law.reference_stiffness(), anisotropic().Q());
  EXPECT_EQ(law.prestress(), S0);
  EXPECT_FALSE(SheetLaw(law).with_wrinkling().affine());
  // affine() promises S = reference_stiffness E + prestress.
  const Vec3 E(0.01, -0.02, 0.005);
  SheetResponse r;
  law.evaluate(E, r);
  EXPECT_EQ(r.S, (law.reference_stiffness() * E + S0).eval());
}

TEST(SheetLawInterface, CopiesCloneAndOtherLawsTakePrestressAndWrinklingThroughWrappers) {
  SheetLaw a(quadratic_law());
  const SheetLaw b = a;
  EXPECT_NE(&a.base(), &b.base());
  EXPECT_EQ(b.name(), "quadratic");
  EXPECT_EQ(a.linear(), nullptr);
  // Any law takes a prestress (added to its stress) and a tension field (sheet_law_wrappers).
  const Vec3 E(0.01, -0.02, 0.005);
  SheetResponse r0, r1;
  a.evaluate(E, r0);
  a.with_prestress({1, 0, 0});
  a.evaluate(E, r1);
  EXPECT_EQ(r1.S, (r0.S + Vec3(1, 0, 0)).eval());
  EXPECT_EQ(a.prestress(), Vec3(1, 0, 0));
  a.with_wrinkling(1e-4);
  EXPECT_TRUE(a.wrinkling());
  EXPECT_EQ(a.slack_stiffness(), 1e-4);
  EXPECT_EQ(a.name(), "quadratic");
  EXPECT_NE(SheetLaw(anisotropic()).linear(), nullptr);
}

TEST(SheetLawInterface, FormFindingLawScalesTheReferenceStiffness) {
  const Vec3 S0(30, -12, 4);
  const SheetLaw law = SheetLaw(anisotropic()).with_prestress(S0).with_wrinkling();
  const SheetLaw ff = form_finding_law(law, 0.5);
  const Mat3 Q = anisotropic().Q();  // a copy: the law returned is a temporary
  EXPECT_EQ(ff.reference_stiffness(), ((0.5 * 30 / Q.diagonal().maxCoeff()) * Q).eval());
  EXPECT_EQ(ff.prestress(), S0);
  EXPECT_TRUE(ff.affine());
  EXPECT_EQ(ff.name(), "aniso");
}

// The membrane patch test with the quadratic law: a 2 x 2 patch of elements in a tilted plane,
// its interior lattice points moved off the lattice, all nodes moved by x = F X. The stress at
// every point is the law's at E = ½(FᵀF − I), the forces at the interior nodes vanish, and each
// element's tangent is the derivative of its force.
template <class Shape>
std::vector<std::array<int, Shape::kNodes>> patch_elements(int m) {
  auto id = [m](int i, int j) { return j * (m + 1) + i; };
  std::vector<std::array<int, Shape::kNodes>> out;
  const int sub = Shape::kNodes > 4 ? 2 : 1;
  for (int j = 0; j < m; j += sub)
    for (int i = 0; i < m; i += sub) {
      auto P = [&](int di, int dj) { return id(i + di, j + dj); };
      if constexpr (std::is_same_v<Shape, shape::Tri3>) {
        out.push_back({P(0, 0), P(1, 0), P(1, 1)});
        out.push_back({P(0, 0), P(1, 1), P(0, 1)});
      } else if constexpr (std::is_same_v<Shape, shape::Quad4>) {
        out.push_back({P(0, 0), P(1, 0), P(1, 1), P(0, 1)});
      } else {
        out.push_back(
            {P(0, 0), P(2, 0), P(2, 2), P(0, 2), P(1, 0), P(2, 1), P(1, 2), P(0, 1), P(1, 1)});
      }
    }
  return out;
}

template <class Shape>
class QuadraticLawPatch : public ::testing::Test {};
using Shapes = ::testing::Types<shape::Tri3, shape::Quad4, shape::Quad9>;
TYPED_TEST_SUITE(QuadraticLawPatch, Shapes);

TYPED_TEST(QuadraticLawPatch, HomogeneousDeformationAndConsistentTangent) {
  using S = TypeParam;
  using M = Membrane<S>;
  test::Random rnd(77 + S::kNodes);
  const SheetLaw law(quadratic_law());
  const LawPoints policy{&law};
  const Mat3 R0 = rnd.rotation(0.7);
  const SheetAxes axes = test::axes_at(30, R0);
  const Mat3 F = Mat3::Identity() + 0.1 * rnd.mat3(-1, 1);
  const Eigen::Matrix<double, 3, 2> Fm =
      F * (Eigen::Matrix<double, 3, 2>() << axes.m1, axes.m2).finished();
  const Mat2 E2 = 0.5 * (Fm.transpose() * Fm - Mat2::Identity());
  const Vec3 E(E2(0, 0), E2(1, 1), 2 * E2(0, 1));
  SheetResponse ref;
  law.evaluate(E, ref);
  ASSERT_GT((ref.S - law.reference_stiffness() * E).norm(), 1e-3 * ref.S.norm())
      << "the deformation must reach the law's nonlinear part";

  const int m = S::kNodes > 4 ? 4 : 2;  // lattice cells per side (two elements per side)
  const double d = 1.0 / m;
  std::vector<Vec3> X0;
  std::vector<bool> interior;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) {
      const bool in = i > 0 && j > 0 && i < m && j < m;
      Vec2 p(i * d, j * d);
      if (in) p += 0.2 * d * Vec2(rnd.uniform(-1, 1), rnd.uniform(-1, 1));
      X0.push_back(R0 * Vec3(p.x(), p.y(), 0));
      interior.push_back(in);
    }
  std::vector<Vec3> f(X0.size(), Vec3::Zero());
  double scale = 0;
  for (const auto& el : patch_elements<S>(m)) {
    typename M::Nodes X, x;
    for (int k = 0; k < S::kNodes; ++k) {
      X.col(k) = X0[el[k]];
      x.col(k) = F * X.col(k);
    }
    typename M::Points pts;
    ASSERT_GT(M::setup(X, law.reference_stiffness(), axes, 0.05, pts), 0);
    for (int q = 0; q < S::kPoints; ++q) {
      // In the sheet axes projected at the point: the same axes here (a flat patch).
      const SheetResponse r = policy.evaluate(pts[q], M::strain(pts[q], x * pts.shapes->dN[q]));
      EXPECT_LT((r.S - ref.S).norm(), 1e-10 * ref.S.norm()) << q;
    }
    typename M::Vector r, r_only;
    typename M::Matrix K;
    M::force_tangent(pts, policy, x, r, K);
    M::force(pts, policy, x, r_only);
    EXPECT_EQ(r, r_only);
    for (int k = 0; k < S::kNodes; ++k) f[el[k]] += r.template segment<3>(3 * k);
    scale = std::max(scale, r.cwiseAbs().maxCoeff());
    const auto K_fd = test::fd_jacobian<typename M::Vector, typename M::Matrix>(
        x, 1e-7, [&](const typename M::Nodes& y, typename M::Vector& out) {
          M::force(pts, policy, y, out);
        });
    EXPECT_LT((K - K_fd).cwiseAbs().maxCoeff(), 1e-6 * K.cwiseAbs().maxCoeff());
  }
  int checked = 0;
  for (size_t n = 0; n < f.size(); ++n)
    if (interior[n]) {
      EXPECT_LT(f[n].norm(), 1e-10 * scale) << "node " << n;
      ++checked;
    }
  EXPECT_GT(checked, 0);
}

TEST(SheetLawInterface, BlocksEvaluateAGeneralLawAndTakeTheFastPathForAnAffineOne) {
  using M = Membrane<shape::Quad4>;
  test::Random rnd(12);
  const NodePositions X =
      test::distorted_element<shape::Quad4>(rnd, 1.0, 0.15, 0.2, rnd.rotation(0.4), Vec3::Zero());
  const NodePositions x = X + 0.05 * Eigen::Matrix<double, 3, 4>::Random();
  const SheetAxes axes = test::axes_at(20, Mat3::Identity());
  const std::vector<int> conn = {0, 1, 2, 3};
  const std::vector<int> all = {0};
  auto block_forces = [&](const SheetLaw& law, M::Vector& r, M::Matrix& K) {
    BlockSetupReport report;
    const auto b = make_membrane_block("quad4", "s", conn, X, law, 1.0, 0.02, &axes,
                                       shape::Integration::kGauss, report);
    b->internal(all, x, r.data(), K.data());
  };
  // The general law through a block: the kernels with LawPoints.
  const SheetLaw quadratic(quadratic_law());
  M::Points pts;
  M::setup(X, quadratic.reference_stiffness(), axes, 0.02, pts);
  M::Vector r_kernel, r_block;
  M::Matrix K_kernel, K_block;
  M::force_tangent(pts, LawPoints{&quadratic}, x, r_kernel, K_kernel);
  block_forces(quadratic, r_block, K_block);
  EXPECT_EQ(r_block, r_kernel);
  EXPECT_EQ(K_block, K_kernel);
  // An affine law other than the linear one: the same bits as the linear law (the fast path).
  const Vec3 S0(20, 10, -3);
  M::Vector r_linear, r_affine;
  M::Matrix K_linear, K_affine;
  block_forces(SheetLaw(anisotropic()).with_prestress(S0), r_linear, K_linear);
  block_forces(SheetLaw(AffineLaw(anisotropic().Q(), S0)), r_affine, K_affine);
  EXPECT_EQ(r_affine, r_linear);
  EXPECT_EQ(K_affine, K_linear);
  // A law with history: the block keeps state_size() doubles per integration point, saved and
  // restored as numbers (checkpoints, staged runs).
  BlockSetupReport report;
  auto blk = make_membrane_block("quad4", "s", conn, X, SheetLaw(HistoryLaw{}), 1.0, 0.02, &axes,
                                 shape::Integration::kGauss, report);
  EXPECT_EQ(blk->history_size(), static_cast<size_t>(blk->size() * 4));
  std::vector<double> saved{7.0};
  blk->save_history(saved);
  EXPECT_EQ(saved.size(), 1 + blk->history_size());
  saved[1] = 3.0;
  EXPECT_EQ(blk->restore_history(saved, 1), saved.size());
  std::vector<double> again;
  blk->save_history(again);
  EXPECT_EQ(again[0], 3.0);
  EXPECT_THROW(blk->restore_history(saved, 2), std::invalid_argument);  // cut short
  // Laws without history keep none.
  EXPECT_EQ(make_membrane_block("quad4", "s", conn, X, SheetLaw(anisotropic()), 1.0, 0.02, &axes,
                                shape::Integration::kGauss, report)
                ->history_size(),
            0u);
}

}  // namespace
}  // namespace velum
