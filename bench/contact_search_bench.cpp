// The sheet contact's search (src/load/face_tree.hpp) at 10k to 1M faces: building the box
// tree, and what every evaluation costs (refit to moved faces, then one point query per node),
// against testing every face (the brute force the tree replaces), on a wavy sheet of
// triangles with its nodes a contact thickness above it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "load/face_tree.hpp"
#include "wavy_sheet.hpp"

namespace {

using velum::Vec3;
using velum::contact::Box;

using Sheet = velum::bench::WavySheet;

using velum::bench::wavy_sheet;

void BM_FaceTreeBuild(benchmark::State& state) {
  const Sheet s = wavy_sheet(static_cast<int>(state.range(0)));
  velum::contact::FaceTree tree;
  for (auto _ : state) {
    tree.build(s.boxes);
    benchmark::ClobberMemory();
  }
  state.SetComplexityN(state.range(0));
}

// One evaluation: refit to the moved faces, then every node's query.
void BM_FaceTreeRefitAndQuery(benchmark::State& state) {
  const Sheet s = wavy_sheet(static_cast<int>(state.range(0)));
  const Sheet moved = wavy_sheet(static_cast<int>(state.range(0)), 0.01);
  velum::contact::FaceTree tree;
  tree.build(s.boxes);
  long found = 0;
  for (auto _ : state) {
    tree.refit(moved.boxes);
    for (const Vec3& p : moved.points) tree.query(p, [&](int) { ++found; });
  }
  benchmark::DoNotOptimize(found);
  state.counters["faces_per_node"] =
      static_cast<double>(found) / static_cast<double>(state.iterations() * moved.points.size());
  state.SetComplexityN(state.range(0));
}

// Every face for every node (1% of the nodes, scaled up in the counter).
void BM_BruteForceQuery(benchmark::State& state) {
  const Sheet s = wavy_sheet(static_cast<int>(state.range(0)));
  long found = 0;
  const size_t step = 100;
  for (auto _ : state)
    for (size_t i = 0; i < s.points.size(); i += step)
      for (const Box& b : s.boxes) found += b.contains(s.points[i]);
  benchmark::DoNotOptimize(found);
  state.counters["times_1pct"] = 1;
}

BENCHMARK(BM_FaceTreeBuild)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity();
BENCHMARK(BM_FaceTreeRefitAndQuery)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity();
BENCHMARK(BM_BruteForceQuery)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
