// Sheet-law throughput in the element kernel (issue 43): Membrane<Quad4>::force and
// ::force_tangent with each law, items_per_second counting integration points: the linear
// anisotropic law on its fast path (D precomputed), the same with wrinkling (evaluated at each
// point), neo-Hookean and Mooney-Rivlin (with and without wrinkling), the elastic-plastic
// ETFE law (a history per point, in a plastic state), the compressible neo-Hookean sheet (a
// scalar Newton per point) and a stress map with an unloading modulus (unloading points). The same
// deformed element as kernels_bench.cpp, scaled so that every law is at a finite stretch. And the
// blocks' pass over a 100 x 100 quad4 sheet with the linear law (the fast path through the block,
// where laws with history added a per-element policy), points per second.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "velum/element/membrane.hpp"
#include "velum/material/compressible_sheet_law.hpp"
#include "velum/material/incompressible_sheet_law.hpp"
#include "velum/material/plastic_sheet_law.hpp"
#include "velum/material/stress_map_sheet_law.hpp"
#include "velum/model/element_block.hpp"

namespace {

using namespace velum;
using Shape = shape::Quad4;
using M = Membrane<Shape>;

PlaneStressLaw linear_law() {
  AnisotropicConstants c;
  c.E1 = 2000, c.E2 = 1000, c.nu12 = 0.3, c.G12 = 400, c.eta1 = 0.25, c.eta2 = -0.15;
  return PlaneStressLaw::anisotropic("bench", c);
}

/// A stiffening fabric map on an 11 x 11 grid, unloading at a modulus above its slopes.
StressMapSheetLaw unloading_map() {
  StressMapData d;
  for (int k = -2; k <= 8; ++k) d.e1.push_back(0.05 * k), d.e2.push_back(0.05 * k);
  for (double e2 : d.e2)
    for (double e1 : d.e1) {
      d.S11.push_back(2000 * e1 + 300 * e2 + 5e4 * e1 * e1 * e1);
      d.S22.push_back(300 * e1 + 1000 * e2 + 5e4 * e2 * e2 * e2);
    }
  d.G12 = 400;
  d.unloading[0] = d.unloading[1] = 1e5;
  return {"map", d};
}

/// The laws by index (the benchmark's argument), and whether the linear fast path applies.
SheetLaw law_of(int k) {
  switch (k) {
    case 0:
    default:
      return SheetLaw(linear_law());
    case 1:
      return SheetLaw(linear_law()).with_wrinkling();
    case 2:
      return SheetLaw(IncompressibleSheetLaw::neo_hookean("nh", 300));
    case 3:
      return SheetLaw(IncompressibleSheetLaw::mooney_rivlin("mr", 150, 15));
    case 4:
      return SheetLaw(IncompressibleSheetLaw::mooney_rivlin("mr", 150, 15)).with_wrinkling();
    case 5:
      return SheetLaw(PlasticSheetLaw::bilinear("etfe", 1100, 0.45, 16, 60));
    case 6:
      return SheetLaw(CompressibleSheetLaw::neo_hookean("cnh", 300, 0.3));
    case 7:
      return SheetLaw(unloading_map());
  }
}
const char* kNames[] = {"linear (fast path)",
                        "linear, wrinkling",
                        "neo_hookean",
                        "mooney_rivlin",
                        "mooney_rivlin, wrinkling",
                        "elastoplastic",
                        "neo_hookean, compressible",
                        "stress_map, unloading"};
constexpr int kLaws = 8;

struct Case {
  M::Points pts;
  M::Nodes x;
  SheetLaw law;
  std::vector<double> history;
  explicit Case(int k) : law(law_of(k)) {
    M::Nodes X;
    const auto nodes = Shape::nodes();
    for (int n = 0; n < Shape::kNodes; ++n) {
      const double u = 0.5 * (nodes[n][0] + 1), v = 0.5 * (nodes[n][1] + 1);
      const double px = u + 0.05 * std::sin(3.1 * n + 1), py = v + 0.05 * std::cos(2.3 * n);
      X.col(n) = Vec3(px, py, 0.1 * (px * px + py * py));
    }
    const double th = 30 * 3.14159265358979 / 180;
    const SheetAxes axes = project_axes(
        {Vec3(std::cos(th), std::sin(th), 0), Vec3(-std::sin(th), std::cos(th), 0), Vec3::UnitZ()},
        M::centre_normal(X));
    M::setup(X, law.reference_stiffness(), axes, 0.01, pts);
    Mat3 F;  // stretch 1.3 / 0.8 with shear, rotated: taut in tension, wrinkled where shortened
    F << 1.3, 0.05, 0.0, -0.03, 0.8, 0.0, 0.02, 0.04, 1.0;
    x = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix() * F * X;
    history.assign(static_cast<size_t>(Shape::kPoints * law.state_size()), 0.0);
    // The plastic law: a history from a step just short of this state, so the points yield;
    // the stress map: from a larger one, so that they unload.
    const double s = k == 7 ? 1.05 : 0.98;
    for (int q = 0; q < Shape::kPoints && law.state_size() > 0; ++q) {
      const Eigen::Matrix<double, 3, 2> g = (s * x + (1 - s) * X) * pts.shapes->dN[q];
      const Vec3 E = sheet_strain_map(pts[q].T) * M::strain(pts[q], g);
      law.base().update_state(E, std::span<double>(history.data() + q * law.state_size(),
                                                   static_cast<size_t>(law.state_size())));
    }
  }
};

template <bool kTangent, class Policy>
void run(benchmark::State& state, const Case& c, const Policy& policy) {
  M::Vector r;
  M::Matrix K;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.x.data());
    if constexpr (kTangent)
      M::force_tangent(c.pts, policy, c.x, r, K);
    else
      M::force(c.pts, policy, c.x, r);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * Shape::kPoints);
}

template <bool kTangent>
void BM_SheetLawKernel(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Case c(k);
  state.SetLabel(kNames[k]);
  if (c.law.state_size() > 0) {
    HistoryLawPoints policy;
    policy.law = &c.law;
    policy.history = c.history.data();
    policy.first = &c.pts.at[0];
    policy.size = c.law.state_size();
    run<kTangent>(state, c, policy);
  } else if (c.law.affine()) {
    run<kTangent>(state, c, ElasticPoints{});
  } else {
    run<kTangent>(state, c, LawPoints{&c.law});
  }
}
BENCHMARK(BM_SheetLawKernel<false>)->Name("BM_SheetLawForce")->DenseRange(0, kLaws - 1);
BENCHMARK(BM_SheetLawKernel<true>)->Name("BM_SheetLawForceTangent")->DenseRange(0, kLaws - 1);

// The block's pass (ElementBlock::internal) over an n x n quad4 sheet with the linear law.
void BM_LinearBlockPass(benchmark::State& state) {
  const int n = 100;
  const bool tangent = state.range(0) != 0;
  NodePositions X(3, (n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) X.col(j * (n + 1) + i) = Vec3(i, j, 0.01 * i * j / n) / n;
  std::vector<int> conn;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      conn.insert(conn.end(), {a, a + 1, a + n + 2, a + n + 1});
    }
  BlockSetupReport report;
  const auto block = make_membrane_block("quad4", "s", conn, X, SheetLaw(linear_law()), 1.0, 0.01,
                                         nullptr, shape::Integration::kGauss, report);
  std::vector<int> elements(static_cast<size_t>(n * n));
  for (int e = 0; e < n * n; ++e) elements[static_cast<size_t>(e)] = e;
  Mat3 F;
  F << 1.08, 0.05, 0.0, -0.03, 0.97, 0.0, 0.02, 0.04, 1.0;
  const NodePositions x = F * X;
  std::vector<double> r(elements.size() * M::kDofs);
  // Aligned as the assembler's buffer is (the block writes each element's matrix as a
  // fixed-size Eigen matrix; a 16-byte aligned std::vector crashed on AVX-512 aligned stores).
  std::vector<double, Eigen::aligned_allocator<double>> K(
      tangent ? elements.size() * M::kDofs * M::kDofs : 0);
  for (auto _ : state) {
    block->internal(elements, x, r.data(), tangent ? K.data() : nullptr);
    benchmark::DoNotOptimize(r.data());
    benchmark::DoNotOptimize(K.data());
  }
  state.SetItemsProcessed(state.iterations() * n * n * Shape::kPoints);
  state.SetLabel(tangent ? "force and tangent" : "force");
}
BENCHMARK(BM_LinearBlockPass)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
