// The support reactions of an enclosed gas: a sphere octant closed by its symmetry planes
// carries at the planes the traction p − p_a on its sheet, as a follower pressure of the same
// value does, although the residual's force (p − p_a) ∂V/∂x of the volume closed by the planes
// differs from it normal to the planes. The whole-run check (equilibrium, −p_g A_z) is in
// tests/cli/inputs_cases.py.
#include <gtest/gtest.h>

#include "../../verification/model_builders.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/model/gas_chamber.hpp"

namespace velum {
namespace {

using test::NodeCache;

// The octant of radius 1 with symmetry planes x = 0, y = 0, z = 0; gas (p0, ambient) when
// `gas`, else a follower pressure `p`.
std::unique_ptr<Model> octant(std::string_view type, bool gas, double p, bool flows = false) {
  auto m = std::make_unique<Model>();
  NodeCache nodes(*m, 1e-9);
  auto conn = test::sphere_octant(nodes, 1.0, 3, type);
  const int b = test::add_membrane(*m, type, std::move(conn),
                                   PlaneStressLaw::isotropic("skin", 1e7, 0.3), 1000.0, 1e-3);
  for (int c = 0; c < 3; ++c)
    m->symmetry.push_back(
        {test::nodes_where(*m, [&](const Vec3& X) { return std::abs(X[c]) < 1e-9; }),
         Vec3::Unit(c)});
  if (!gas) {
    test::add_pressure(*m, b, p);
    return m;
  }
  GasLoad g;
  g.parts.push_back({b, {}});
  for (int e = 0; e < m->blocks[b]->size(); ++e) g.parts[0].elements.push_back(e);
  g.initial_pressure = 1.2e5;
  g.ambient = 1.0e5;
  g.gamma = 1.4;
  if (flows) g.temperature = 300.0, g.gas_constant = 287.0;  // mass and energy tracked
  m->gases.push_back(std::move(g));
  set_up_gas_chamber(*m, m->gases[0]);
  return m;
}

TEST(GasChamber, ReactionsAreTheTractionsOfTheGas) {
  for (const char* type : {"tri3", "quad4", "quad9"}) {
    auto gas = octant(type, true, 0);
    MechanicalSystem gs(*gas);
    std::srand(5);
    const VecX u = 1e-2 * VecX::Random(gs.size());
    const double t = 0.5;
    // The gauge pressure at u, from the gas's own volume.
    const NodePositions x = gas->X + gs.displacements(t, u);
    const GasLoad& g = gas->gases[0];
    const double gauge = g.pressure(gas_chamber_volume(*gas, g, x), 1.0) - g.ambient;
    auto follower = octant(type, false, gauge);
    MechanicalSystem fs(*follower);
    ASSERT_EQ(fs.size(), gs.size());
    const NodePositions Rg = gs.reactions(t, u, VecX::Zero(gs.size()));
    const NodePositions Rf = fs.reactions(t, u, VecX::Zero(fs.size()));
    EXPECT_LT((Rg - Rf).cwiseAbs().maxCoeff(), 1e-9 * Rf.cwiseAbs().maxCoeff()) << type;
    // The closed form: the forces the supports carry sum to p_g A_z, A_z the area the sheet
    // projects on z = 0 (the quarter disc, to the mesh's accuracy); the residual's ∂V/∂x
    // sums to a third of it.
    const double pg = g.initial_pressure - g.ambient;
    const VecX zero = VecX::Zero(gs.size());
    const double at_supports = gs.external_forces(0, zero, zero, true).row(2).sum();
    const double residual = gs.external_forces(0, zero, zero).row(2).sum();
    EXPECT_NEAR(at_supports / pg, M_PI / 4, 0.02) << type;
    EXPECT_NEAR(residual / pg, M_PI / 12, 0.01) << type;
  }
}

// A chamber with gas flow loads its supports the same way (its own term, gas_flow_term.cpp).
TEST(GasChamber, ReactionsOfAChamberWithGasFlowAreTheTractionsOfTheGas) {
  for (const char* type : {"tri3", "quad4"}) {
    auto gas = octant(type, true, 0, true);
    ASSERT_TRUE(gas->gases[0].flows());
    MechanicalSystem gs(*gas);
    const VecX zero = VecX::Zero(gs.size());
    gs.start_loads(0, zero, zero);  // the gas state at the start
    const double pg = gas->gases[0].initial_pressure - gas->gases[0].ambient;
    const double at_supports = gs.external_forces(0, zero, zero, true).row(2).sum();
    const double residual = gs.external_forces(0, zero, zero).row(2).sum();
    EXPECT_NEAR(at_supports / pg, M_PI / 4, 0.02) << type;
    EXPECT_NEAR(residual / pg, M_PI / 12, 0.01) << type;
  }
}

}  // namespace
}  // namespace velum
