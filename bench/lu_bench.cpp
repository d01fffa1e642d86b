// Factorisation of one unsymmetric Jacobian by the LU back-ends (KLU with its pivot order
// reused, the supernodal LU, UMFPACK), CPU time per numeric factorisation and per solve. The
// matrix is a Matrix Market file named by VELUM_LU_MATRIX (a Jacobian of the C9 canopy, for
// instance), or the first step's Jacobian of the model file it names when the name ends in
// .yaml (out/bench/c9-profile/isotropic.yaml, written by bench/c9-profile); without it the
// benchmarks are skipped. Counters: `mflop` of the supernodal LU's panels, `gflops` = that over
// the CPU time.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string_view>
#include <unsupported/Eigen/SparseExtra>

#include "model_jacobian.hpp"
#include "solve/supernodal_lu.hpp"
#include "velum/solve/linear_solver.hpp"

namespace {

using namespace velum;

const SparseMatrix* matrix() {
  static const SparseMatrix* A = [] {
    const char* file = std::getenv("VELUM_LU_MATRIX");
    if (!file) return static_cast<SparseMatrix*>(nullptr);
    if (std::string_view(file).ends_with(".yaml"))
      return new SparseMatrix(bench::model_jacobian(file));
    auto* M = new SparseMatrix;
    if (!Eigen::loadMarket(*M, file)) return static_cast<SparseMatrix*>(nullptr);
    M->makeCompressed();
    return M;
  }();
  return A;
}

std::unique_ptr<LinearSolver> make(int which) {
  if (which == 1) return std::make_unique<SupernodalLu>();
  return make_linear_solver(which == 0 ? SolverKind::kKlu : SolverKind::kUmfpack);
}

void BM_Factorise(benchmark::State& state) {
  const SparseMatrix* A = matrix();
  if (!A) {
    state.SkipWithError("VELUM_LU_MATRIX names no Matrix Market file");
    return;
  }
  auto solver = make(static_cast<int>(state.range(0)));
  if (!solver->refactorize(*A)) state.SkipWithError("factorisation failed");
  for (auto _ : state) benchmark::DoNotOptimize(solver->factorize(*A));
  state.SetLabel(std::string(solver->name()));
  if (auto* lu = dynamic_cast<SupernodalLu*>(solver.get())) {
    state.counters["mflop"] = lu->structure().flops * 1e-6;
    state.counters["supernodes"] = lu->structure().supernodes();
    state.counters["gflops"] = benchmark::Counter(lu->structure().flops * 1e-9,
                                                  benchmark::Counter::kIsIterationInvariantRate);
  }
}
BENCHMARK(BM_Factorise)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_Solve(benchmark::State& state) {
  const SparseMatrix* A = matrix();
  if (!A) {
    state.SkipWithError("VELUM_LU_MATRIX names no Matrix Market file");
    return;
  }
  auto solver = make(static_cast<int>(state.range(0)));
  if (!solver->refactorize(*A)) state.SkipWithError("factorisation failed");
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A->rows(), -1.0, 2.0);
  Eigen::VectorXd x;
  for (auto _ : state) benchmark::DoNotOptimize(solver->solve(b, x));
  state.counters["residual"] = (*A * x - b).norm() / (A->norm() * x.norm());
  state.SetLabel(std::string(solver->name()));
}
BENCHMARK(BM_Solve)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

// The supernodal LU with other amalgamation rules: 0 fundamental supernodes only, 1 the
// default (CHOLMOD's), 2 looser, 3 any supernode up to 16 columns absorbs its child.
void BM_Amalgamation(benchmark::State& state) {
  const SparseMatrix* A = matrix();
  if (!A) {
    state.SkipWithError("VELUM_LU_MATRIX names no Matrix Market file");
    return;
  }
  Amalgamation relax;
  switch (state.range(0)) {
    case 0:
      relax = {0, 0, 0, 0, 0.0, 0.0, 0.0};
      break;
    case 2:
      relax = {8, 32, 96, 256, 0.9, 0.2, 0.1};
      break;
    case 3:
      relax = {16, 32, 64, 256, 0.8, 0.1, 0.05};
      break;
    default:
      break;
  }
  SupernodalLu lu(relax);
  if (!lu.refactorize(*A)) state.SkipWithError("factorisation failed");
  for (auto _ : state) benchmark::DoNotOptimize(lu.factorize(*A));
  state.counters["mflop"] = lu.structure().flops * 1e-6;
  state.counters["supernodes"] = lu.structure().supernodes();
  state.counters["panel_MB"] = 8e-6 * static_cast<double>(lu.structure().values);
}
BENCHMARK(BM_Amalgamation)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
