// Cutting patterns of a large roof: a 4 m hypar (0.8 m twist) of 224 x 224 cells as 100,352
// tri3, cut into 8 strip panels of 6,525 nodes, each flattened (conformal start, least-energy
// Gauss-Newton, warp along the strips) as `velum pattern` does, without reading or writing
// files; with the orthotropic PVC's law (second argument 1) and with the isotropic energy
// (0). One iteration: the figure is the wall time of the whole roof (docs/patterns.md).
#include <benchmark/benchmark.h>

#include <algorithm>

#include "velum/analysis/flatten.hpp"

namespace {

using namespace velum;

void BM_PatternRoof(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), strips = 8, per = n / strips;
  const double length = 4.0, twist = 0.8;
  auto node = [n](int i, int j) { return j * (n + 1) + i; };
  NodePositions x(3, (n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double u = double(i) / n, v = double(j) / n;
      x.col(node(i, j)) << length * u, length * v, twist * (u * (1 - v) + v * (1 - u));
    }
  std::vector<PanelMesh> panels(strips);
  for (int p = 0; p < strips; ++p)
    for (int j = p * per; j < (p + 1) * per; ++j)
      for (int i = 0; i < n; ++i) {
        panels[p].triangles.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1)});
        panels[p].triangles.push_back({node(i, j), node(i + 1, j + 1), node(i, j + 1)});
        panels[p].warp.insert(panels[p].warp.end(), 2, Vec3(1, 0, 0));
      }
  FlattenSettings settings;  // second argument 0: the isotropic energy (nu 0.3)
  if (state.range(1)) settings.stiffness << 6e8, 1.35e8, 0, 1.35e8, 4.5e8, 0, 0, 0, 3e7;  // PVC
  double worst = 0;
  int iterations = 0;
  for (auto _ : state) {
    for (const auto& mesh : panels) {
      const FlatPanel flat = flatten_panel(x, mesh, settings);
      worst = std::max(worst, flat.max_strain);
      iterations = std::max(iterations, flat.iterations);
    }
  }
  state.counters["elements"] = 2.0 * n * per * strips;
  state.counters["panels"] = strips;
  state.counters["max_strain"] = worst;
  state.counters["gauss_newton_iterations"] = iterations;
}
BENCHMARK(BM_PatternRoof)
    ->Args({224, 1})
    ->Args({224, 0})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
