// Assembly and linear-solver throughput on the pressurised square membrane: internal force +
// tangent (+ follower-pressure load stiffness) per element count and thread count, and the
// three direct solvers' analyse / factorise / solve on the resulting Jacobian.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <array>
#include <chrono>

#include "solve/supernodal_cholesky.hpp"
#include "square_membrane.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/solve/linear_solver.hpp"

namespace {

using namespace velum;

// Arguments: elements per side, threads.
void BM_AssembleTangent(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  auto model = pressurised_square(n);
  MechanicalSystem sys(*model);
  VecX u = VecX::Random(sys.size()) * 1e-3, v = VecX::Zero(sys.size()), a = v, r;
  SparseMatrix J;
  for (auto _ : state) {
    sys.evaluate(0.0, u, v, a, 1.0, 0.0, 1.0, r, &J);
    benchmark::DoNotOptimize(J.valuePtr());
  }
  state.counters["elements"] =
      benchmark::Counter(double(n) * n * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["dofs"] = sys.size();
  omp_set_num_threads(omp_get_num_procs());
}
BENCHMARK(BM_AssembleTangent)
    ->ArgsProduct({{50, 100, 200}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Arguments: elements per side, solver (0 cholmod, 1 umfpack, 2 klu, 3 mumps, 4 the
// supernodal Cholesky, 5 the same without its tree split), threads. Time per factorisation;
// analysis and one solve are reported as counters, and for the supernodal Cholesky its flops
// (`gflop`) and rate (`gflops`, per second of wall time), with its tree split's shares (`top_share`
// of the flops in the top, `group_share` of the groups' flops in group 1).
void BM_Factorize(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(2)));
  const SolverKind kind =
      std::array{SolverKind::kCholmod, SolverKind::kUmfpack, SolverKind::kKlu,
                 SolverKind::kMumps,   SolverKind::kAuto,    SolverKind::kAuto}[state.range(1)];
  if (kind == SolverKind::kMumps && !have_mumps()) {
    state.SkipWithError("built without MUMPS");
    return;
  }
  auto model = pressurised_square(n);
  MechanicalSystem sys(*model);
  VecX u = VecX::Zero(sys.size()), v = u, a = u, r, x;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, 1.0, 0.0, 1.0, r, &J);  // K + M: symmetric positive definite
  std::unique_ptr<LinearSolver> solver;
  if (state.range(1) == 4)
    solver = std::make_unique<SupernodalCholesky>();
  else if (state.range(1) == 5)  // without the tree split
    solver = std::make_unique<SupernodalCholesky>(Amalgamation{}, 1e300);
  else
    solver = make_linear_solver(kind);
  auto t0 = std::chrono::steady_clock::now();
  solver->analyze(J);
  const double analyse =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (auto _ : state) benchmark::DoNotOptimize(solver->factorize(J));
  t0 = std::chrono::steady_clock::now();
  solver->solve(r, x);
  state.counters["solve_s"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  state.counters["analyse_s"] = analyse;
  state.counters["dofs"] = sys.size();
  state.counters["nonzeros"] = static_cast<double>(J.nonZeros());
  state.SetLabel(std::string(solver->name()));
  if (auto* chol = dynamic_cast<SupernodalCholesky*>(solver.get())) {
    state.counters["gflop"] = chol->structure().flops * 1e-9;
    state.counters["gflops"] = benchmark::Counter(chol->structure().flops * 1e-9,
                                                  benchmark::Counter::kIsIterationInvariantRate);
    const TreeSplit& split = chol->split();  // the tree split's share of the flops
    state.counters["top_share"] = split.flops[2] / chol->structure().flops;
    state.counters["group_share"] = split.flops[1] / std::max(1.0, split.flops[0] + split.flops[1]);
    const SupernodalCholesky::SplitSeconds& t = chol->split_seconds();  // the last one's
    state.counters["group0_s"] = t.group[0];
    state.counters["group1_s"] = t.group[1];
    state.counters["top_s"] = t.top;
    state.counters["top_supernodes"] = static_cast<double>(split.top.size());
  }
  omp_set_num_threads(omp_get_num_procs());
}
BENCHMARK(BM_Factorize)
    ->ArgsProduct({{50, 100, 200, 225}, {0, 1, 2, 3, 4, 5}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
