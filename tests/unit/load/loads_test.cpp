// The loads' room: each load's forces against its matrix (central finite differences, on an
// anisotropic membrane), the rank-one gas term, the payload drag's velocity Jacobian, a step's
// held load, copies (clone), the summing order and the typed views of Model's one list.
#include <gtest/gtest.h>

#include <iostream>

#include "../../verification/model_builders.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/analysis/stages.hpp"
#include "velum/model/gas_chamber.hpp"

namespace velum {
namespace {

using test::NodeCache;

// A curved quad9 patch of an anisotropic, prestressed sheet; a corner node fixed.
std::unique_ptr<Model> anisotropic_patch() {
  auto m = std::make_unique<Model>();
  NodeCache nodes(*m, 1e-9);
  std::vector<int> conn;
  test::mesh_patch(
      nodes, [](double u, double v) { return Vec3(u, 0.8 * v, 0.2 * u * u + 0.1 * u * v); }, 2, 2,
      "quad9", conn);
  AnisotropicConstants c;
  c.E1 = 2000.0, c.E2 = 1000.0, c.nu12 = 0.3, c.G12 = 400.0, c.eta1 = 0.25, c.eta2 = -0.15;
  test::add_membrane(*m, "quad9", std::move(conn),
                     SheetLaw(PlaneStressLaw::anisotropic("aniso", c)).with_prestress({5, 7, 2}),
                     1000.0, 1e-3);
  m->fixed.push_back({{0}, {true, true, true}});
  return m;
}

// The load term i of `sys` at displacements u: its forces over the equations, and, with
// J, its load stiffness and low-rank part as J = −∂f/∂u (dense).
VecX load_forces(MechanicalSystem& sys, size_t i, double t, const VecX& u, MatX* J) {
  const Model& m = sys.model();
  NodePositions U = NodePositions::Zero(3, m.num_nodes());
  sys.dofs().scatter(u, U);
  const NodePositions x = m.X + U, V = NodePositions::Zero(3, m.num_nodes());
  NodePositions F = NodePositions::Zero(3, m.num_nodes());
  SparseMatrix K;
  LowRankJacobian L;
  const int cols = sys.loads()[i]->low_rank_columns();
  if (J) {
    sys.assembler().make_matrix(K);
    L.U.setZero(sys.size(), cols);
    L.W.setZero(sys.size(), cols);
  }
  LoadOutput out{.F = F, .K = J ? &K : nullptr, .low_rank = &L, .column = 0};
  sys.loads()[i]->add(LoadState{.t = t, .x = x, .V = V}, out);
  if (J) *J = MatX(K) + L.U * L.W.transpose();
  VecX f;
  sys.dofs().gather(F, f);
  return f;
}

// max |J + ∂f/∂u| / max |∂f/∂u| for load term i (central differences).
double load_matrix_error(MechanicalSystem& sys, size_t i, double t) {
  const int n = sys.size();
  std::srand(7);
  const VecX u = 2e-2 * VecX::Random(n);
  MatX J;
  load_forces(sys, i, t, u, &J);
  MatX fd(n, n);
  const double h = 1e-7;
  for (int k = 0; k < n; ++k) {
    VecX e = VecX::Zero(n);
    e[k] = h;
    fd.col(k) =
        (load_forces(sys, i, t, u + e, nullptr) - load_forces(sys, i, t, u - e, nullptr)) / (2 * h);
  }
  return (J + fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
}

TEST(Loads, PressureMatricesMatchFiniteDifferences) {
  for (int kind = 0; kind < 3; ++kind) {
    auto m = anisotropic_patch();
    PressureLoad p;
    p.block = 0;
    p.value = 300.0;
    p.elements = {0, 1, 3};  // not the whole block: the load's own pass
    if (kind > 0) {
      p.fixed_direction = true;
      p.direction = Vec3(0.3, -0.2, 1).normalized();
      p.projected = kind == 1;
    }
    m->pressures.push_back(p);
    MechanicalSystem sys(*m);
    const double err = load_matrix_error(sys, 0, 0.0);
    std::cout << "pressure kind " << kind << ": relative error " << err << "\n";
    EXPECT_LT(err, 1e-6) << kind;
  }
}

TEST(Loads, FusedFollowerPressureMatchesItsOwnPass) {
  // The whole block's follower pressure goes through the internal pass (evaluate), and gives
  // the same residual as the load's own pass (external_forces).
  auto m = anisotropic_patch();
  test::add_pressure(*m, 0, 250.0);
  MechanicalSystem sys(*m);
  int block = -1;
  double p = 0;
  EXPECT_TRUE(sys.loads()[0]->whole_block_pressure(0.0, block, p));
  EXPECT_EQ(block, 0);
  EXPECT_EQ(p, 250.0);
  std::srand(5);
  const VecX u = 1e-2 * VecX::Random(sys.size()), zero = VecX::Zero(sys.size());
  VecX r;
  SparseMatrix J;
  sys.evaluate(0.0, u, zero, zero, 1, 0, 0, r, &J);
  const NodePositions fused = sys.last_external();
  const NodePositions own = sys.external_forces(0.0, u, zero);
  EXPECT_LT((fused - own).cwiseAbs().maxCoeff(), 1e-12 * own.cwiseAbs().maxCoeff());
}

TEST(Loads, GasMatrixWithRankOneTermMatchesFiniteDifferences) {
  auto m = std::make_unique<Model>();
  NodeCache nodes(*m, 1e-9);
  auto conn = test::sphere_octant(nodes, 1.0, 2, "quad9");
  AnisotropicConstants c;
  c.E1 = 2000.0, c.E2 = 1000.0, c.nu12 = 0.3, c.G12 = 400.0, c.eta1 = 0.25, c.eta2 = -0.15;
  const int b = test::add_membrane(*m, "quad9", std::move(conn),
                                   SheetLaw(PlaneStressLaw::anisotropic("aniso", c)), 1000.0, 1e-3);
  for (int k = 0; k < 3; ++k)
    m->symmetry.push_back(
        {test::nodes_where(*m, [&](const Vec3& X) { return std::abs(X[k]) < 1e-9; }),
         Vec3::Unit(k)});
  GasLoad gas;
  gas.parts.push_back({b, {}});
  for (int e = 0; e < m->blocks[b]->size(); ++e) gas.parts[0].elements.push_back(e);
  gas.initial_pressure = 1.2e5, gas.ambient = 1.0e5, gas.gamma = 1.4;
  gas.amount = test::add_ramp(*m, 2.0);
  m->gases.push_back(gas);
  m->loads[0].set_up(*m);
  EXPECT_NEAR(m->gases[0].V0, M_PI / 6, 2e-4);
  MechanicalSystem sys(*m);
  EXPECT_EQ(sys.loads()[0]->low_rank_columns(), 1);
  const double err = load_matrix_error(sys, 0, 1.2);
  std::cout << "gas: relative error " << err << "\n";
  EXPECT_LT(err, 1e-6);
  // Its history quantities: at the last evaluation, and at any state.
  const NodePositions x = m->X;
  EXPECT_NEAR(*sys.load_quantity_at("gas_volume", 0, 1.2, x), m->gases[0].V0, 1e-12);
  EXPECT_FALSE(sys.load_quantity("gas_volume", 1));
}

TEST(Loads, EdgeAndGravityForcesAreConstantWithoutMatrix) {
  auto m = anisotropic_patch();
  m->edge_loads.push_back(
      {.nodes = test::nodes_where(*m, [](const Vec3& X) { return X.x() > 1 - 1e-9; }),
       .force_per_length = Vec3(1, 2, 3)});
  m->gravity.push_back({Vec3(0, 0, -9.81), -1});
  m->loads[0].set_up(*m);
  MechanicalSystem sys(*m);
  for (size_t i = 0; i < 2; ++i) {
    MatX J;
    const VecX zero = VecX::Zero(sys.size());
    const VecX f0 = load_forces(sys, i, 0.0, zero, &J);
    EXPECT_EQ(J.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(load_forces(sys, i, 0.0, VecX::Constant(sys.size(), 0.1), nullptr), f0);
  }
  // The edge load's resultant: force per length times the loaded edge's length (the straight
  // side x = 1, from (1, 0, 0.2) to (1, 0.8, 0.3)).
  const NodePositions F = edge_load_forces(*m, m->edge_loads[0]);
  EXPECT_NEAR(F.row(1).sum(), 2 * std::sqrt(0.8 * 0.8 + 0.1 * 0.1), 1e-12);
  // An edge load on no boundary edge is an error of its set-up.
  m->edge_loads[0].nodes = {0};
  EXPECT_THROW(m->loads[0].set_up(*m), std::invalid_argument);
}

TEST(Loads, DragVelocityJacobianMatchesFiniteDifferences) {
  auto m = anisotropic_patch();
  m->masses.push_back({4, 2.0});
  m->drag.push_back({4, 1.2, 0.7});
  MechanicalSystem sys(*m);
  const int n = sys.size();
  std::srand(3);
  const VecX u = 1e-2 * VecX::Random(n), v = VecX::Random(n), a = VecX::Zero(n);
  VecX r, rp, rm;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, 0, 1, 0, r, &J);
  const MatX Jd(J);
  MatX fd(n, n);
  const double h = 1e-7;
  for (int k = 0; k < n; ++k) {
    VecX e = VecX::Zero(n);
    e[k] = h;
    sys.evaluate(0.0, u, v + e, a, 0, 1, 0, rp, nullptr);
    sys.evaluate(0.0, u, v - e, a, 0, 1, 0, rm, nullptr);
    fd.col(k) = (rp - rm) / (2 * h);
  }
  EXPECT_GT(fd.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LT((Jd - fd).cwiseAbs().maxCoeff(), 1e-6 * fd.cwiseAbs().maxCoeff());
  // The drag on a point mass's own fields is refused (it is a load).
  auto old = anisotropic_patch();
  old->masses.push_back({4, 2.0, 1.2, 0.7});
  EXPECT_THROW(MechanicalSystem{*old}, std::invalid_argument);
}

TEST(Loads, HeldLoadsKeepTheirValueAtTheStepsEnd) {
  Model before;
  before.add_node(1, Vec3::Zero());
  const int ramp = test::add_ramp(before, 2.0);
  before.point_loads.push_back({{0}, Vec3(2, 0, 0), ramp});
  before.gravity.push_back({Vec3(0, 0, -10), ramp});
  GasLoad gas;
  gas.amount = ramp;
  gas.V0 = 3;
  before.gases.push_back(gas);
  Model step;
  step.add_node(1, Vec3::Zero());
  step.functions = before.functions;
  step.loads = before.loads;
  hold_loads(step, before, 0.5);
  EXPECT_EQ(step.point_loads[0].force, Vec3(0.5, 0, 0));
  EXPECT_EQ(step.point_loads[0].function, -1);
  EXPECT_EQ(step.gravity[0].acceleration, Vec3(0, 0, -2.5));
  ASSERT_EQ(step.gases[0].amount, 1);  // a constant function of the amount at 0.5
  EXPECT_EQ(step.function_value(step.gases[0].amount, 7.0), 0.25);
  EXPECT_EQ(step.gases[0].V0, 3);
  // The load before is untouched.
  EXPECT_EQ(before.point_loads[0].function, ramp);
  // Loads that do not match are an error.
  Model other;
  other.gravity.push_back({});
  EXPECT_THROW(hold_loads(other, before, 0.5), std::logic_error);
}

TEST(Loads, CopiesAreDeepAndViewsFollowTheirModel) {
  Model a;
  a.gravity.push_back({Vec3(0, 0, -1), -1});
  a.point_loads.push_back({{0}, Vec3(1, 0, 0), -1});  // summed before gravity: first
  EXPECT_EQ(a.loads[0].kind(), "point");
  EXPECT_EQ(a.loads[1].kind(), "gravity");
  EXPECT_EQ(load_counts(a.loads), "1 point, 0 edge, 0 pressure, 1 gravity");
  Model b;
  b.loads = a.loads;
  b.point_loads[0].force = Vec3(5, 0, 0);
  EXPECT_EQ(a.point_loads[0].force, Vec3(1, 0, 0));
  Model c(std::move(b));
  EXPECT_EQ(c.point_loads.size(), 1u);
  EXPECT_EQ(c.point_loads[0].force, Vec3(5, 0, 0));
  c.point_loads.push_back({{0}, Vec3(6, 0, 0), -1});
  EXPECT_EQ(c.point_loads.size(), 2u);
  EXPECT_EQ(c.loads.size(), 3u);
  std::unique_ptr<Load> copy = c.loads[0].clone();
  dynamic_cast<PointLoad&>(*copy).force = Vec3::Zero();
  EXPECT_EQ(c.point_loads[0].force, Vec3(5, 0, 0));
  // Directed and follower pressures: two classes, one view.
  PressureLoad p;
  p.fixed_direction = true;
  c.pressures.push_back(p);
  c.pressures.push_back({});
  EXPECT_EQ(c.pressures.size(), 2u);
  EXPECT_TRUE(c.pressures[0].fixed_direction);
  EXPECT_FALSE(c.pressures[1].fixed_direction);
}

TEST(Loads, PiecesKeepTheirNodesLoads) {
  Model m;
  m.point_loads.push_back({{0, 1, 2}, Vec3(1, 0, 0), -1});
  m.drag.push_back({1, 1.0, 1.0});
  m.drag.push_back({2, 1.0, 1.0});
  const std::vector<int> local_of = {-1, 0, -1};
  m.loads.keep_if([&](Load& l) { return l.keep_piece(m, {}, local_of); });
  ASSERT_EQ(m.loads.size(), 2u);
  EXPECT_EQ(m.point_loads[0].nodes, std::vector<int>{0});
  EXPECT_EQ(m.drag.size(), 1u);
  EXPECT_EQ(m.drag[0].node, 0);
}

}  // namespace
}  // namespace velum
