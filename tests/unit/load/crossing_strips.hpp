// Two strips 0.6 m long and one element (5 cm) wide, three elements long, crossing each
// other at their middles, both in one self-contact set with edge contact (docs/contact.md,
// "Sheets"): no node of either lies over the other's faces, so only edge pairs act. An anisotropic
// law (the penalty follows its stiffness). The edge tests share it (edge_contact_test.cpp,
// edge_friction_test.cpp).
#pragma once

#include <memory>

#include "../../verification/model_builders.hpp"
#include "velum/load/contact_load.hpp"

namespace velum::test {

struct CrossingStrips {
  double thickness = 1e-3;  ///< each strip's: the contact distance across the pair
  double z0 = 0.002;        ///< the upper strip's height over the lower one
  bool edges = true;
  double mu = 0;
  /// How the upper strip is held: kPulledDown (its ends moved down by `drop` by t = 1, its
  /// inner nodes free in z only), kSlid (its inner nodes pressed down by `press` newtons each
  /// up to t = 1, then its ends moved along x by `slide` up to t = 2; the inner nodes free in x
  /// and z), kPressed (both strips held at their ends only, the upper one's inner nodes pressed
  /// down by `press` newtons each up to t = 1) or kEndsHeld (as kPressed, nothing applied:
  /// the term's checks). The lower strip is held whole in the first two.
  enum class Held { kPulledDown, kSlid, kPressed, kEndsHeld } held = Held::kPulledDown;
  double drop = 0.006, press = 2.0, slide = 0;
};

inline std::unique_ptr<Model> crossing_strips(const CrossingStrips& o) {
  auto out = std::make_unique<Model>();
  Model& m = *out;
  AnisotropicConstants c;
  c.E1 = 1e9, c.E2 = 6e8, c.nu12 = 0.3, c.G12 = 3e8, c.eta1 = 0.2, c.eta2 = -0.1;
  for (int layer = 0; layer < 2; ++layer) {
    NodeCache nodes(m, 1e-9);
    std::vector<int> conn;
    mesh_patch(
        nodes,
        [&](double u, double v) {
          const double along = -0.3 + 0.6 * u, across = -0.025 + 0.05 * v;
          return layer ? Vec3(along, across, o.z0) : Vec3(across, along, 0.0);
        },
        3, 1, "quad4", conn);
    const double S = 1000.0 / o.thickness;
    add_membrane(m, "quad4", std::move(conn),
                 SheetLaw(PlaneStressLaw::anisotropic("aniso", c)).with_prestress({S, S, 0}),
                 1000.0, o.thickness);
  }
  std::vector<int> lower, lower_ends, ends, middle;  // middle: the upper strip's inner nodes
  for (int i = 0; i < m.num_nodes(); ++i) {
    const Vec3 X = m.X.col(i);
    if (X.z() < 0.5 * o.z0) {
      lower.push_back(i);
      if (std::abs(X.y()) > 0.2) lower_ends.push_back(i);
    } else if (std::abs(X.x()) < 0.2) {
      middle.push_back(i);
    } else {
      ends.push_back(i);
    }
  }
  auto table = [&](std::vector<std::pair<double, double>> points) {
    TimeFunction f;
    f.kind = TimeFunction::Kind::kTable;
    f.points = std::move(points);
    f.name = "table";
    m.functions.push_back(f);
    return static_cast<int>(m.functions.size()) - 1;
  };
  switch (o.held) {
    case CrossingStrips::Held::kPulledDown:
      m.fixed.push_back({lower, {true, true, true}});
      m.fixed.push_back({middle, {true, true, false}});
      m.prescribed.push_back({ends, Vec3(0, 0, -o.drop), add_ramp(m, 1.0)});
      break;
    case CrossingStrips::Held::kSlid: {
      m.fixed.push_back({lower, {true, true, true}});
      m.fixed.push_back({middle, {false, true, false}});
      const int pressed = table({{0, 0}, {1, 1}});
      for (int n : middle) m.point_loads.push_back({{n}, Vec3(0, 0, -o.press), pressed});
      m.prescribed.push_back({ends, Vec3(o.slide, 0, 0), table({{0, 0}, {1, 0}, {2, 1}})});
      break;
    }
    case CrossingStrips::Held::kPressed:
    case CrossingStrips::Held::kEndsHeld:
      m.fixed.push_back({lower_ends, {true, true, true}});
      m.fixed.push_back({ends, {true, true, true}});
      if (o.held == CrossingStrips::Held::kPressed)
        for (int n : middle) m.point_loads.push_back({{n}, Vec3(0, 0, -o.press), add_ramp(m, 1)});
      break;
  }
  ContactLoad cl;
  cl.self = true;
  cl.edges = o.edges;
  cl.friction = o.mu;
  for (int b = 0; b < 2; ++b) {
    cl.parts.push_back({b, {}});
    for (int e = 0; e < m.blocks[static_cast<size_t>(b)]->size(); ++e)
      cl.parts.back().elements.push_back(e);
  }
  m.loads.add(make_load(cl));
  for (auto& l : m.loads) l->set_up(m);
  return out;
}

}  // namespace velum::test
