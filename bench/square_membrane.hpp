// The benchmark problem shared by bench/*: a pressurised square membrane of n x n quad4.
#pragma once

#include <cmath>
#include <memory>
#include <numbers>

#include "velum/model/model.hpp"

namespace velum {

// Square [0, 1]² of n x n quad4 (E t = 1e6 N/m, ν = 0.3, ρ t = 1 kg/m²), edges clamped, lifted
// to z = rise · sin(πx) sin(πy) (flat at rise 0), no load.
inline std::unique_ptr<Model> clamped_square(int n, double rise = 0) {
  auto m = std::make_unique<Model>();
  const double pi = std::numbers::pi;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, y = double(j) / n;
      m->add_node(j * (n + 1) + i + 1, Vec3(x, y, rise * std::sin(pi * x) * std::sin(pi * y)));
    }
  std::vector<int> conn;
  std::vector<int> edge;
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      conn.insert(conn.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      if (i == 0 || j == 0 || i == n || j == n) edge.push_back(id(i, j));
  BlockSetupReport report;
  m->blocks.push_back(make_membrane_block("quad4", "sheet", std::move(conn), m->X,
                                          PlaneStressLaw::isotropic("film", 1e9, 0.3), 1000.0, 1e-3,
                                          nullptr, shape::Integration::kGauss, report));
  m->fixed.push_back({edge, {true, true, true}});
  return m;
}

// The flat square above under a 100 Pa follower pressure.
inline std::unique_ptr<Model> pressurised_square(int n) {
  auto m = clamped_square(n);
  PressureLoad p;
  p.block = 0;
  p.value = 100;
  for (int e = 0; e < m->blocks[0]->size(); ++e) p.elements.push_back(e);
  m->pressures.push_back(std::move(p));
  return m;
}

}  // namespace velum
