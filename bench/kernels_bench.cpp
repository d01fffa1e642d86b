// Element-kernel throughput: Membrane<Shape>::force and ::force_tangent for every surface shape
// with the anisotropic law, and the cable kernels. items_per_second counts integration points;
// the `elements` counter is elements per second. Geometry: a slightly distorted, curved element
// of size ~1 with axes at 30 degrees, in a deformed state (stretch, shear and rotation).
#include <benchmark/benchmark.h>

#include <cmath>

#include "rotated_stretch.hpp"
#include "velum/element/cable.hpp"
#include "velum/element/membrane.hpp"
#include "velum/material/plane_stress.hpp"

namespace {

using namespace velum;

PlaneStressLaw bench_law() {
  AnisotropicConstants c;
  c.E1 = 2000, c.E2 = 1000, c.nu12 = 0.3, c.G12 = 400, c.eta1 = 0.25, c.eta2 = -0.15;
  return PlaneStressLaw::anisotropic("bench", c);
}

using velum::bench::rotated_stretch;

template <class Shape>
struct MembraneCase {
  using M = Membrane<Shape>;
  typename M::Points pts;
  typename M::Nodes x;

  MembraneCase() {
    typename M::Nodes X;
    const auto nodes = Shape::nodes();
    const bool tri = Shape::kNodes == 3 || Shape::kNodes == 6;
    for (int n = 0; n < Shape::kNodes; ++n) {
      const double u = tri ? nodes[n][0] : 0.5 * (nodes[n][0] + 1);
      const double v = tri ? nodes[n][1] : 0.5 * (nodes[n][1] + 1);
      // Deterministic distortion (about 5%) and a shallow bulge.
      const double px = u + 0.05 * std::sin(3.1 * n + 1), py = v + 0.05 * std::cos(2.3 * n);
      X.col(n) = Vec3(px, py, 0.1 * (px * px + py * py));
    }
    const double th = 30 * 3.14159265358979 / 180;
    const SheetAxes axes = project_axes(
        {Vec3(std::cos(th), std::sin(th), 0), Vec3(-std::sin(th), std::cos(th), 0), Vec3::UnitZ()},
        M::centre_normal(X));
    M::setup(X, bench_law().Q(), axes, 0.01, pts);
    x = rotated_stretch() * X;
  }
};

template <class Shape>
void set_counters(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations() * Shape::kPoints);
  state.counters["elements"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

template <class Shape>
void BM_MembraneForce(benchmark::State& state) {
  MembraneCase<Shape> c;
  typename Membrane<Shape>::Vector r;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::force(c.pts, c.x, r);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
}

template <class Shape>
void BM_MembraneForceTangent(benchmark::State& state) {
  MembraneCase<Shape> c;
  typename Membrane<Shape>::Vector r;
  typename Membrane<Shape>::Matrix K;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::force_tangent(c.pts, c.x, r, K);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
}

// The same kernel through a sheet law evaluated at each point (LawPoints): the tension field
// (wrinkling) on, in the deformed state above, where every point is wrinkled (stretched along
// one axis, shortened along the other); the `wrinkled` counter is the share of wrinkled points.
template <class Shape>
void BM_MembraneForceTangentWrinkled(benchmark::State& state) {
  MembraneCase<Shape> c;
  const SheetLaw law = SheetLaw(bench_law()).with_wrinkling();
  const LawPoints policy{&law};
  typename Membrane<Shape>::Vector r;
  typename Membrane<Shape>::Matrix K;
  int wrinkled = 0;
  for (int q = 0; q < Shape::kPoints; ++q) {
    const Eigen::Matrix<double, 3, 2> g = c.x * c.pts.shapes->dN[q];
    wrinkled += policy.evaluate(c.pts[q], Membrane<Shape>::strain(c.pts[q], g)).state ==
                WrinkleState::kWrinkled;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::force_tangent(c.pts, policy, c.x, r, K);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
  state.counters["wrinkled"] = static_cast<double>(wrinkled) / Shape::kPoints;
}

template <class Shape>
void BM_MembranePressureTangent(benchmark::State& state) {
  MembraneCase<Shape> c;
  typename Membrane<Shape>::Vector f;
  typename Membrane<Shape>::Matrix K;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Membrane<Shape>::pressure_force_tangent(c.pts, c.x, 1.0, f, K);
    benchmark::DoNotOptimize(f.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
}

template <class Shape>
struct CableCase {
  using C = Cable<Shape>;
  typename C::Points pts;
  typename C::Nodes x;
  CableLaw law{5.7e10, false};

  CableCase() {
    typename C::Nodes X;
    X.col(0) = Vec3(0, 0, 0);
    X.col(1) = Vec3(1, 0.2, 0.1);
    if constexpr (Shape::kNodes == 3) X.col(2) = Vec3(0.5, 0.12, 0.04);
    C::setup(X, law.E, 2.2783e-4, pts);
    x = 1.01 * rotated_stretch() * X;
  }
};

template <class Shape>
void BM_CableForce(benchmark::State& state) {
  CableCase<Shape> c;
  typename Cable<Shape>::Vector r;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Cable<Shape>::force(c.pts, c.law, c.x, r);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
}

template <class Shape>
void BM_CableForceTangent(benchmark::State& state) {
  CableCase<Shape> c;
  typename Cable<Shape>::Vector r;
  typename Cable<Shape>::Matrix K;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    Cable<Shape>::force_tangent(c.pts, c.law, c.x, r, K);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  set_counters<Shape>(state);
}

using namespace velum::shape;
BENCHMARK(BM_MembraneForce<Tri3>);
BENCHMARK(BM_MembraneForce<Tri6>);
BENCHMARK(BM_MembraneForce<Quad4>);
BENCHMARK(BM_MembraneForce<Quad8>);
BENCHMARK(BM_MembraneForce<Quad9>);
BENCHMARK(BM_MembraneForceTangent<Tri3>);
BENCHMARK(BM_MembraneForceTangent<Tri6>);
BENCHMARK(BM_MembraneForceTangent<Quad4>);
BENCHMARK(BM_MembraneForceTangent<Quad8>);
BENCHMARK(BM_MembraneForceTangent<Quad9>);
BENCHMARK(BM_MembraneForceTangentWrinkled<Quad4>);
BENCHMARK(BM_MembraneForceTangentWrinkled<Quad9>);
BENCHMARK(BM_MembranePressureTangent<Tri3>);
BENCHMARK(BM_MembranePressureTangent<Quad4>);
BENCHMARK(BM_MembranePressureTangent<Quad9>);
BENCHMARK(BM_CableForce<Line2>);
BENCHMARK(BM_CableForce<Line3>);
BENCHMARK(BM_CableForceTangent<Line2>);
BENCHMARK(BM_CableForceTangent<Line3>);

}  // namespace
