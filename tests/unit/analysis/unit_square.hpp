// The small sheet models and settings the explicit-dynamics tests share: a unit square of
// n x n quad4 in z = 0 (nodes 1 to (n + 1)² row by row), its edge and inner nodes, the square
// clamped under a follower pressure, and a central-difference run.
#pragma once

#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/material/linear_sheet_law.hpp"
#include "velum/model/model.hpp"

namespace velum::test {

struct UnitSquare {
  std::vector<int> conn;   ///< quad4 connectivity (node indices), row by row
  std::vector<int> edge;   ///< the nodes on the square's edges
  std::vector<int> inner;  ///< the others
  int n = 0;
  int id(int i, int j) const { return j * (n + 1) + i; }
};

/// Adds the (n + 1)² nodes of the unit square to m and returns its elements and node lists.
inline UnitSquare add_unit_square(Model& m, int n) {
  UnitSquare sq;
  sq.n = n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_node(sq.id(i, j) + 1, Vec3(double(i) / n, double(j) / n, 0));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      sq.conn.insert(sq.conn.end(),
                     {sq.id(i, j), sq.id(i + 1, j), sq.id(i + 1, j + 1), sq.id(i, j + 1)});
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      (i == 0 || j == 0 || i == n || j == n ? sq.edge : sq.inner).push_back(sq.id(i, j));
  return sq;
}

/// A square of 4 x 4 quad4 (1 m, E t = 1 MN/m, ρ t = 1 kg/m²) clamped at its edges under a
/// follower pressure, with or without an isotropic prestress (without: flat, it is stiff in
/// its plane only; pressed out, its membrane strain stiffens it).
inline Model pressurised_square(double pressure, double prestress) {
  Model m;
  UnitSquare sq = add_unit_square(m, 4);
  LinearSheetLaw law(PlaneStressLaw::isotropic("film", 1e9, 0.3));
  if (prestress != 0) law.with_prestress(Vec3(prestress, prestress, 0));
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block("quad4", "sheet", std::move(sq.conn), m.X, law, 1000.0,
                                         1e-3, nullptr, shape::Integration::kGauss, report));
  m.fixed.push_back({sq.edge, {true, true, true}});
  PressureLoad p;
  p.block = 0;
  p.value = pressure;
  for (int e = 0; e < 16; ++e) p.elements.push_back(e);
  m.pressures.push_back(std::move(p));
  return m;
}

/// A central-difference run to t_end; `step` is capped at the stable step's fraction.
inline AnalysisSettings explicit_run(double t_end, double step = 1.0) {
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kDynamic;
  s.scheme = "central-difference";
  s.time.step = step;
  s.time.t_end = t_end;
  return s;
}

}  // namespace velum::test
