// Enclosed gas through the system: the set-up checks of a chamber (closure with symmetry
// planes, consistent and outward normals), and the Jacobian of MechanicalSystem with a gas
// load (follower stiffness in the sparse matrix plus the rank-one p(V) coupling kept apart)
// against central finite differences of the residual, static and shifted as in dynamics.
#include <gtest/gtest.h>

#include <iostream>

#include "../../verification/model_builders.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/model/gas_chamber.hpp"

namespace velum {
namespace {

using test::NodeCache;

// A sphere octant of radius R with symmetry planes x = 0, y = 0, z = 0 and a gas load on it.
std::unique_ptr<Model> gas_octant(std::string_view type, int n, bool symmetry = true,
                                  bool flip = false) {
  auto m = std::make_unique<Model>();
  NodeCache nodes(*m, 1e-9);
  auto conn = test::sphere_octant(nodes, 1.0, n, type);
  if (flip) {  // reverse every element: normals into the gas
    const int nn = type == "quad9" ? 9 : type == "quad4" ? 4 : 3;
    for (size_t e = 0; e < conn.size(); e += nn)
      if (nn == 9) {
        std::swap(conn[e + 1], conn[e + 3]);
        std::swap(conn[e + 4], conn[e + 7]);
        std::swap(conn[e + 5], conn[e + 6]);
      } else {
        std::swap(conn[e + 1], conn[e + nn - 1]);
      }
  }
  const int b = test::add_membrane(*m, type, std::move(conn),
                                   PlaneStressLaw::isotropic("skin", 1e7, 0.3), 1000.0, 1e-3);
  if (symmetry)
    for (int c = 0; c < 3; ++c)
      m->symmetry.push_back(
          {test::nodes_where(*m, [&](const Vec3& X) { return std::abs(X[c]) < 1e-9; }),
           Vec3::Unit(c)});
  GasLoad gas;
  gas.parts.push_back({b, {}});
  for (int e = 0; e < m->blocks[b]->size(); ++e) gas.parts[0].elements.push_back(e);
  gas.initial_pressure = 1.2e5;
  gas.ambient = 1.0e5;
  gas.gamma = 1.4;
  m->gases.push_back(std::move(gas));
  return m;
}

std::string setup_error(Model& m) {
  try {
    set_up_gas_chamber(m, m.gases[0]);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

TEST(GasChamber, ClosedBySymmetryPlanesHasTheOctantVolume) {
  auto m = gas_octant("quad9", 4);
  EXPECT_EQ(setup_error(*m), "");
  const double exact = M_PI / 6;  // an eighth of 4π/3
  EXPECT_NEAR(m->gases[0].V0, exact, 2e-4 * exact);
}

// A chamber's initial volume is measured where the sheet starts (mesh.reference_positions:
// X + U0), as an airbag's is its folded volume: the octant with a flat stress-free reference
// (its nodes pressed onto z = 0, which encloses nothing) has the octant's volume.
TEST(GasChamber, InitialVolumeIsTheStartVolume) {
  auto m = gas_octant("quad9", 4);
  const NodePositions start = m->X;
  NodePositions flat = start;
  flat.row(2).setZero();
  BlockSetupReport report;
  m->blocks[0] = make_membrane_block("quad9", "sheet", m->blocks[0]->connectivity(), flat,
                                     PlaneStressLaw::isotropic("skin", 1e7, 0.3), 1000.0, 1e-3,
                                     nullptr, shape::Integration::kGauss, report);
  m->X = flat;
  EXPECT_NE(setup_error(*m).find("zero to round-off"), std::string::npos);
  m->U0 = start - flat;
  EXPECT_EQ(setup_error(*m), "");
  const double exact = M_PI / 6;
  EXPECT_NEAR(m->gases[0].V0, exact, 2e-4 * exact);
  EXPECT_DOUBLE_EQ(m->gases[0].V0, gas_chamber_volume(*m, m->gases[0], start));
}

TEST(GasChamber, OpenSurfaceIsAnError) {
  auto m = gas_octant("quad4", 3, false);
  const std::string why = setup_error(*m);
  EXPECT_NE(why.find("the surface is not closed"), std::string::npos) << why;
  // Symmetry planes that do not pass through the origin do not close it either.
  auto shifted = gas_octant("quad4", 3);
  shifted->gases[0].origin = Vec3(0.1, 0, 0);
  EXPECT_NE(setup_error(*shifted).find("not closed"), std::string::npos);
}

TEST(GasChamber, InwardNormalsAreAnError) {
  for (const char* type : {"tri3", "quad4", "quad9"}) {
    auto m = gas_octant(type, 2, true, true);
    const std::string why = setup_error(*m);
    EXPECT_NE(why.find("point into the gas"), std::string::npos) << type << ": " << why;
  }
}

TEST(GasChamber, InconsistentNormalsAreAnError) {
  auto m = gas_octant("quad4", 3);
  // Rebuild the block with one element reversed.
  std::vector<int> conn = m->blocks[0]->connectivity();
  std::swap(conn[4 * 4 + 1], conn[4 * 4 + 3]);
  BlockSetupReport report;
  m->blocks[0] =
      make_membrane_block("quad4", "sheet", conn, m->X, PlaneStressLaw::isotropic("skin", 1e7, 0.3),
                          1000.0, 1e-3, nullptr, shape::Integration::kGauss, report);
  const std::string why = setup_error(*m);
  EXPECT_NE(why.find("run the same way"), std::string::npos) << why;
}

// Two independent chambers: the octant of gas_octant and a second octant of radius 0.7
// centred at (3, 0, 0) (its own nodes, planes x = 3, y = 0, z = 0, origin there) with its
// own gas (another pressure and gamma).
std::unique_ptr<Model> two_chambers(std::string_view type) {
  auto m = gas_octant(type, 2);
  const int first = m->num_nodes();
  NodeCache nodes(*m, 1e-9);
  auto conn = test::sphere_octant(nodes, 0.7, 2, type);
  for (int n = first; n < m->num_nodes(); ++n) m->X(0, n) += 3.0;
  const int b = test::add_membrane(*m, type, std::move(conn),
                                   PlaneStressLaw::isotropic("skin", 2e7, 0.25), 1000.0, 1e-3);
  std::vector<int> on_x, on_y, on_z;
  for (int n = first; n < m->num_nodes(); ++n) {
    if (std::abs(m->X(0, n) - 3.0) < 1e-9) on_x.push_back(n);
    if (std::abs(m->X(1, n)) < 1e-9) on_y.push_back(n);
    if (std::abs(m->X(2, n)) < 1e-9) on_z.push_back(n);
  }
  m->symmetry.push_back({on_x, Vec3::UnitX()});
  m->symmetry.push_back({on_y, Vec3::UnitY()});
  m->symmetry.push_back({on_z, Vec3::UnitZ()});
  GasLoad gas;
  gas.parts.push_back({b, {}});
  for (int e = 0; e < m->blocks[b]->size(); ++e) gas.parts[0].elements.push_back(e);
  gas.initial_pressure = 2.0e5;
  gas.ambient = 1.0e5;
  gas.gamma = 1.0;
  gas.origin = Vec3(3, 0, 0);
  m->gases.push_back(std::move(gas));
  return m;
}

// ‖J_full − J_fd‖ / ‖J_fd‖ with J_full = J + U Wᵀ; `with_low_rank` false leaves the rank-one
// coupling out (to show the check can fail).
double gas_jacobian_error(std::string_view type, double cu, double cv, double ca,
                          bool with_low_rank = true, bool two = false) {
  auto m = two ? two_chambers(type) : gas_octant(type, 2);
  for (auto& gas : m->gases) set_up_gas_chamber(*m, gas);
  m->gases[0].amount = test::add_ramp(*m, 2.0);  // amount 0.6 at t = 1.2
  MechanicalSystem sys(*m);
  const int n = sys.size();
  std::srand(3);
  const VecX u = 2e-2 * VecX::Random(n), v = 0.1 * VecX::Random(n), a = VecX::Random(n);
  const double t = 1.2;
  VecX r, rp, rm;
  SparseMatrix J;
  sys.evaluate(t, u, v, a, cu, cv, ca, r, &J);
  MatX Jd = MatX(J);
  const auto& L = sys.jacobian_low_rank();
  EXPECT_EQ(L.U.cols(), cu != 0 ? static_cast<int>(m->gases.size()) : 0);
  if (with_low_rank && L.U.cols() > 0) Jd += L.U * L.W.transpose();
  MatX Jfd(n, n);
  const double h = 1e-7;
  for (int k = 0; k < n; ++k) {
    VecX e = VecX::Zero(n);
    e[k] = h;
    sys.evaluate(t, u + cu * e, v + cv * e, a + ca * e, cu, cv, ca, rp, nullptr);
    sys.evaluate(t, u - cu * e, v - cv * e, a - ca * e, cu, cv, ca, rm, nullptr);
    Jfd.col(k) = (rp - rm) / (2 * h);
  }
  return (Jd - Jfd).cwiseAbs().maxCoeff() / Jfd.cwiseAbs().maxCoeff();
}

TEST(GasChamber, JacobianWithRankOneCouplingMatchesFiniteDifferences) {
  for (const char* type : {"tri3", "quad4", "quad9"})
    for (auto [cu, cv, ca] : {std::array{1.0, 0.0, 0.0}, std::array{0.7, 0.3, 5.0}}) {
      const double err = gas_jacobian_error(type, cu, cv, ca);
      const double without = gas_jacobian_error(type, cu, cv, ca, false);
      std::cout << type << " (cu, cv, ca) = (" << cu << ", " << cv << ", " << ca
                << "): relative error " << err << ", without the rank-one term " << without << "\n";
      EXPECT_LT(err, 1e-6);
      EXPECT_GT(without, 1e-3);  // the coupling is a visible part of the tangent
    }
}

TEST(GasChamber, TwoChambersAreIndependentColumns) {
  auto m = two_chambers("quad4");
  for (auto& gas : m->gases) set_up_gas_chamber(*m, gas);
  EXPECT_NEAR(m->gases[1].V0 / m->gases[0].V0, 0.7 * 0.7 * 0.7, 1e-12);
  const double err = gas_jacobian_error("quad4", 1.0, 0.0, 0.0, true, true);
  std::cout << "two chambers: relative error " << err << "\n";
  EXPECT_LT(err, 1e-6);
}

}  // namespace
}  // namespace velum

namespace velum {
namespace {

// The tangent with gas flow (an inflator, a vent, a quadratic leak through the walls, and with
// `two` an orifice to the second chamber) against central differences of the residual, at a
// state past a committed step: the rank-one columns carry ∂p/∂V and ∂p/∂A of the local solve.
double gas_flow_jacobian_error(bool two, bool with_low_rank) {
  auto m = two ? two_chambers("quad4") : gas_octant("quad4", 2);
  for (auto& gas : m->gases) {
    set_up_gas_chamber(*m, gas);
    gas.gamma = 1.4, gas.temperature = 300, gas.gas_constant = 287;
  }
  GasLoad& g = m->gases[0];
  g.inflators.push_back({test::add_ramp(*m, 0.01), 0.5, 600, -1});
  gas::Vent vent;
  vent.area = 1e-3, vent.discharge = 0.8;
  g.vents.push_back(vent);
  g.leaks.push_back({g.parts, 2e-6, 1e3});
  if (two) g.orifices.push_back({1, 5e-3, 0.7});
  MechanicalSystem sys(*m);
  const int n = sys.size();
  std::srand(5);
  const VecX zero = VecX::Zero(n), u0 = 1e-2 * VecX::Random(n);
  sys.start_loads(0, zero, zero);
  sys.accept(1e-3, u0, zero);
  const VecX u = u0 + 1e-2 * VecX::Random(n), v = zero, a = zero;
  const double t = 2e-3;
  VecX r, rp, rm;
  SparseMatrix J;
  sys.evaluate(t, u, v, a, 1.0, 0.0, 0.0, r, &J);
  MatX Jd = MatX(J);
  const auto& L = sys.jacobian_low_rank();
  EXPECT_EQ(L.U.cols(), static_cast<int>(m->gases.size()));
  if (with_low_rank) Jd += L.U * L.W.transpose();
  MatX Jfd(n, n);
  const double h = 1e-7;
  for (int k = 0; k < n; ++k) {
    VecX e = VecX::Zero(n);
    e[k] = h;
    sys.evaluate(t, u + e, v, a, 1.0, 0.0, 0.0, rp, nullptr);
    sys.evaluate(t, u - e, v, a, 1.0, 0.0, 0.0, rm, nullptr);
    Jfd.col(k) = (rp - rm) / (2 * h);
  }
  return (Jd - Jfd).cwiseAbs().maxCoeff() / Jfd.cwiseAbs().maxCoeff();
}

TEST(GasChamber, JacobianWithGasFlowMatchesFiniteDifferences) {
  for (bool two : {false, true}) {
    const double err = gas_flow_jacobian_error(two, true);
    const double without = gas_flow_jacobian_error(two, false);
    std::cout << (two ? "two chambers and an orifice" : "one chamber")
              << " with inflator, vent and leak: relative error " << err
              << ", without the low-rank columns " << without << "\n";
    EXPECT_LT(err, 1e-6);
    EXPECT_GT(without, 1e-3);
  }
}

}  // namespace
}  // namespace velum
