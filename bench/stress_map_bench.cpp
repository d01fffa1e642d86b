// The stress-map sheet law's cost (issue 43): the law alone (points per second of evaluate) and
// Membrane<Shape>::force / ::force_tangent through laws evaluated at each point (LawPoints),
// the stress map beside the linear orthotropic law it was tabulated from, on the element and
// deformed state of kernels_bench.cpp. items_per_second counts integration points.
#include <benchmark/benchmark.h>

#include <cmath>

#include "rotated_stretch.hpp"
#include "velum/element/membrane.hpp"
#include "velum/material/plane_stress.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/material/stress_map_sheet_law.hpp"

namespace {

using namespace velum;

PlaneStressLaw orthotropic_law() {
  return PlaneStressLaw::orthotropic("bench", 2000, 1000, 0.3, 400, false);
}

/// The linear law on an 11 x 11 grid with a cubic stiffening, G12 as the linear law's.
SheetLaw map_law() {
  const Mat3 Q = orthotropic_law().Q();
  StressMapData d;
  for (int k = -4; k <= 6; ++k) d.e1.push_back(0.025 * k), d.e2.push_back(0.025 * k);
  for (double e2 : d.e2)
    for (double e1 : d.e1) {
      d.S11.push_back(Q(0, 0) * e1 + Q(0, 1) * e2 + 5e4 * e1 * e1 * e1);
      d.S22.push_back(Q(1, 0) * e1 + Q(1, 1) * e2 + 5e4 * e2 * e2 * e2);
    }
  d.G12 = Q(2, 2);
  return SheetLaw(StressMapSheetLaw("map", d));
}

/// Forces the linear law off its fast path: the same law, not affine.
class PointwiseLinear final : public SheetLawBase {
 public:
  explicit PointwiseLinear(const PlaneStressLaw& l) : law_(l) {}
  const std::string& name() const override { return law_.name(); }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override {
    law_.evaluate(E, h, out);
  }
  double energy(const Vec3& E, std::span<const double> h) const override {
    return law_.energy(E, h);
  }
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return law_.reference_stiffness(); }
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<PointwiseLinear>(*this);
  }

 private:
  LinearSheetLaw law_;
};

using velum::bench::rotated_stretch;

template <class Shape>
struct ElementCase {
  using M = Membrane<Shape>;
  typename M::Points pts;
  typename M::Nodes x;
  explicit ElementCase(const Mat3& Q) {
    typename M::Nodes X;
    const auto nodes = Shape::nodes();
    const bool tri = Shape::kNodes == 3 || Shape::kNodes == 6;
    for (int n = 0; n < Shape::kNodes; ++n) {
      const double u = tri ? nodes[n][0] : 0.5 * (nodes[n][0] + 1);
      const double v = tri ? nodes[n][1] : 0.5 * (nodes[n][1] + 1);
      const double px = u + 0.05 * std::sin(3.1 * n + 1), py = v + 0.05 * std::cos(2.3 * n);
      X.col(n) = Vec3(px, py, 0.1 * (px * px + py * py));
    }
    const double th = 30 * 3.14159265358979 / 180;
    const SheetAxes axes = project_axes(
        {Vec3(std::cos(th), std::sin(th), 0), Vec3(-std::sin(th), std::cos(th), 0), Vec3::UnitZ()},
        M::centre_normal(X));
    M::setup(X, Q, axes, 0.01, pts);
    x = rotated_stretch() * X;
  }
};

SheetLaw linear_or_map(int which) {
  return which == 0 ? SheetLaw(PointwiseLinear(orthotropic_law())) : map_law();
}

void label(benchmark::State& state) {
  state.SetLabel(state.range(0) == 0 ? "linear" : "stress_map");
}

// The law alone, at strains spread over the grid.
void BM_SheetLawEvaluate(benchmark::State& state) {
  const SheetLaw law = linear_or_map(static_cast<int>(state.range(0)));
  Vec3 E[64];
  for (int k = 0; k < 64; ++k)
    E[k] = Vec3(0.002 * (k % 8) - 0.004, 0.003 * (k / 8) - 0.006, 0.001 * (k % 5));
  SheetResponse r;
  int k = 0;
  for (auto _ : state) {
    law.evaluate(E[k++ & 63], r);
    benchmark::DoNotOptimize(r.S.data());
    benchmark::DoNotOptimize(r.C.data());
  }
  state.SetItemsProcessed(state.iterations());
  label(state);
}

template <class Shape>
void BM_MembraneForceLaw(benchmark::State& state) {
  const SheetLaw law = linear_or_map(static_cast<int>(state.range(0)));
  ElementCase<Shape> c(law.reference_stiffness());
  const LawPoints policy{&law};
  typename Membrane<Shape>::Vector r;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::force(c.pts, policy, c.x, r);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * Shape::kPoints);
  label(state);
}

template <class Shape>
void BM_MembraneForceTangentLaw(benchmark::State& state) {
  const SheetLaw law = linear_or_map(static_cast<int>(state.range(0)));
  ElementCase<Shape> c(law.reference_stiffness());
  const LawPoints policy{&law};
  typename Membrane<Shape>::Vector r;
  typename Membrane<Shape>::Matrix K;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::force_tangent(c.pts, policy, c.x, r, K);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * Shape::kPoints);
  label(state);
}

using namespace velum::shape;

BENCHMARK(BM_SheetLawEvaluate)->Arg(0)->Arg(1);
BENCHMARK(BM_MembraneForceLaw<Tri3>)->Arg(0)->Arg(1);
BENCHMARK(BM_MembraneForceLaw<Quad4>)->Arg(0)->Arg(1);
BENCHMARK(BM_MembraneForceTangentLaw<Tri3>)->Arg(0)->Arg(1);
BENCHMARK(BM_MembraneForceTangentLaw<Quad4>)->Arg(0)->Arg(1);

}  // namespace
