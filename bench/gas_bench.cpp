// One Newton iteration (tangent and residual, factorisation, solve) on a clamped dome with a
// follower pressure, and on the same mesh with the pressure coming from an enclosed gas (the
// dome closed by the plane z = 0 its clamped edge lies on): the cost of the gas coupling
// (volume and its Hessian in the assembly, one extra back-substitution per factorisation for
// the rank-one term, the Sherman-Morrison correction per solve). One thread, CPU time.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <numbers>

#include "square_membrane.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/model/gas_chamber.hpp"
#include "velum/time/low_rank_solver.hpp"

namespace {

using namespace velum;

std::unique_ptr<Model> dome(int n, bool gas) {
  auto m = clamped_square(n, 0.1);
  std::vector<int> all(static_cast<size_t>(m->blocks[0]->size()));
  for (size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
  if (gas) {
    GasLoad g;
    g.parts.push_back({0, all});
    g.initial_pressure = 1.01325e5 + 1e4;
    g.ambient = 1.01325e5;
    g.gamma = 1.4;
    m->gases.push_back(std::move(g));
    set_up_gas_chamber(*m, m->gases[0]);
  } else {
    m->pressures.push_back({0, all, 1e4, -1});
  }
  return m;
}

// Arguments: elements per side, gas (0: the same gauge pressure as a follower load).
void BM_NewtonIteration(benchmark::State& state) {
  omp_set_num_threads(1);
  auto model = dome(static_cast<int>(state.range(0)), state.range(1) != 0);
  MechanicalSystem sys(*model);
  const VecX u = VecX::Random(sys.size()) * 1e-4, zero = VecX::Zero(sys.size());
  VecX r, du;
  SparseMatrix J;
  auto sparse = make_linear_solver(SolverKind::kAuto);
  LowRankCorrectedSolver solver(*sparse, sys);
  for (auto _ : state) {
    sys.evaluate(1.0, u, zero, zero, 1.0, 0.0, 0.0, r, &J);
    if (!solver.refactorize(J) || !solver.solve(-r, du)) state.SkipWithError("solve failed");
    benchmark::DoNotOptimize(du.data());
  }
  state.counters["dofs"] = sys.size();
  state.SetLabel(std::string(solver.name()) + (state.range(1) ? " gas" : " pressure"));
  omp_set_num_threads(omp_get_num_procs());
}
BENCHMARK(BM_NewtonIteration)
    ->ArgsProduct({{100, 200}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();

}  // namespace
