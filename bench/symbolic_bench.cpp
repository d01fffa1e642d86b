// The supernodal Cholesky's symbolic analysis on the pressurised square's Jacobian (3 equations
// per node), by part: the nested dissection of the node graph (`order_s`, and its CPU time
// `order_cpu_s`), the supernodal structure from it (`supernodes_s`), and the whole analyze() with
// its panel plans and allocations (time per iteration). Minima over the iterations; `gflop` of the
// factorisation.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include <time.h>

#include "solve/ordering.hpp"
#include "solve/supernodal_cholesky.hpp"
#include "solve/supernodes.hpp"
#include "square_membrane.hpp"
#include "velum/analysis/mechanical_system.hpp"

namespace {

using namespace velum;

// Arguments: elements per side, threads.
void BM_Symbolic(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  auto model = pressurised_square(n);
  MechanicalSystem sys(*model);
  VecX u = VecX::Zero(sys.size()), v = u, a = u, r;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, 1.0, 0.0, 1.0, r, &J);
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  };
  auto cpu = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
  };
  double order_s = std::numeric_limits<double>::infinity(), supernodes_s = order_s;
  double order_cpu_s = order_s;
  double flops = 0, values = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto t0 = Clock::now();
    const double c0 = cpu();
    const std::vector<int> position = nested_dissection(J);
    order_cpu_s = std::min(order_cpu_s, cpu() - c0);
    order_s = std::min(order_s, seconds(t0));
    t0 = Clock::now();
    const SupernodalStructure st = analyse_supernodes(J, position, {}, Factor::kCholesky);
    supernodes_s = std::min(supernodes_s, seconds(t0));
    flops = st.flops;
    values = static_cast<double>(st.values);
    SupernodalCholesky solver;
    state.ResumeTiming();
    benchmark::DoNotOptimize(solver.analyze(J));
  }
  state.counters["order_s"] = order_s;
  state.counters["order_cpu_s"] = order_cpu_s;
  state.counters["supernodes_s"] = supernodes_s;
  state.counters["gflop"] = flops * 1e-9;
  state.counters["panel_values"] = values;  // L, its diagonal blocks whole
  state.counters["dofs"] = sys.size();
  omp_set_num_threads(omp_get_num_procs());
}
BENCHMARK(BM_Symbolic)
    ->ArgsProduct({{100, 225}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
