// A wedge (a rigid mesh with one ridge) under an anisotropic strip one element wide: the edge
// contact tests with a rigid mesh (rigid_edge_test.cpp, rigid_edge_friction_test.cpp).
#pragma once

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "../../verification/model_builders.hpp"
#include "load/rigid_mesh.hpp"
#include "velum/load/contact_load.hpp"

namespace velum::test {

inline constexpr double kT = 1e-3;  // the strip's thickness: contact distance 0.5 mm

// A wedge (a triangular prism, its faces' normals out of it): its ridge along y at x = 0,
// z = top, from y = −0.1 to 0.1, its slopes down to z = top − 0.05 at x = ±0.05.
inline RigidBody wedge(double top) {
  std::vector<Vec3> v = {{0, -0.1, top},
                         {0, 0.1, top},
                         {-0.05, -0.1, top - 0.05},
                         {-0.05, 0.1, top - 0.05},
                         {0.05, -0.1, top - 0.05},
                         {0.05, 0.1, top - 0.05}};
  std::vector<std::array<int, 3>> t = {{0, 1, 3}, {0, 3, 2}, {0, 4, 5}, {0, 5, 1},
                                       {2, 3, 5}, {2, 5, 4}, {0, 2, 4}, {1, 5, 3}};
  RigidBody b;
  b.name = "wedge";
  b.shape = RigidBody::Shape::kMesh;
  b.point = Vec3(0, 0, top - 0.02);
  b.mesh = make_rigid_mesh(std::move(v), std::move(t));
  return b;
}

// A prestressed anisotropic strip 0.6 m x 5 cm along x, three elements long, its ends held; its
// inner nodes free in z only (or in all directions: `free_inner`). With slide >= 0 its ends moved
// along y by `slide` from t = 1 to 2 instead of held (and its inner nodes pressed down by `press`
// newtons each up to t = 1).
inline std::unique_ptr<Model> strip(bool free_inner, double slide = -1, double press = 2.0) {
  auto m = std::make_unique<Model>();
  test::NodeCache nodes(*m, 1e-9);
  std::vector<int> conn;
  test::mesh_patch(
      nodes, [](double u, double v) { return Vec3(-0.3 + 0.6 * u, -0.025 + 0.05 * v, 0.0); }, 3, 1,
      "quad4", conn);
  AnisotropicConstants c;
  c.E1 = 1e9, c.E2 = 6e8, c.nu12 = 0.3, c.G12 = 3e8, c.eta1 = 0.2, c.eta2 = -0.1;
  const double S = 1000.0 / kT;
  test::add_membrane(*m, "quad4", std::move(conn),
                     SheetLaw(PlaneStressLaw::anisotropic("aniso", c)).with_prestress({S, S, 0}),
                     1000.0, kT);
  const std::vector<int> ends =
      test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.x()) > 0.2; });
  if (slide < 0) {
    m->fixed.push_back({ends, {1, 1, 1}});
  } else {
    auto table = [&](std::vector<std::pair<double, double>> points) {
      TimeFunction f;
      f.kind = TimeFunction::Kind::kTable;
      f.points = std::move(points);
      f.name = "table";
      m->functions.push_back(f);
      return static_cast<int>(m->functions.size()) - 1;
    };
    m->prescribed.push_back({ends, Vec3(0, slide, 0), table({{0, 0}, {1, 0}, {2, 1}})});
    const int pressed = table({{0, 0}, {1, 1}});
    for (int n : test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.x()) < 0.2; }))
      m->point_loads.push_back({{n}, Vec3(0, 0, -press), pressed});
  }
  if (!free_inner)
    m->fixed.push_back(
        {test::nodes_where(*m, [](const Vec3& X) { return std::abs(X.x()) < 0.2; }), {1, 1, 0}});
  return m;
}

}  // namespace velum::test
