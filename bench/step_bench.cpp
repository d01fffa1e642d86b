// Whole-step timing: one implicit dynamic step (trapezoidal Newmark, 4 full Newton
// iterations) on a 200 x 200 quad4 square membrane under follower pressure (about 120k DOF),
// split into assembly (MechanicalSystem::evaluate with the shifted Jacobian), numeric
// factorisation (LinearSolver::refactorize; the symbolic analysis is done once beforehand,
// with a first factorisation, and reported as `analyse_s`) and triangular solves. Counters are
// seconds per step: `*_s` wall clock, `*_cpu_s` CPU time of all the process's threads
// (getrusage; the honest figure on a shared, loaded machine); `peak_rss_MB` is the process's
// peak resident set.
#include <benchmark/benchmark.h>

#include <chrono>

#include "process_cpu.hpp"
#include "square_membrane.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/model/model.hpp"

namespace {

using namespace velum;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// User + system CPU seconds of the whole process (all threads).
using velum::bench::process_cpu;

void BM_ImplicitStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto model = pressurised_square(n);
  MechanicalSystem sys(*model);
  auto solver = make_linear_solver(SolverKind::kAuto);
  const int neq = sys.size();
  const double h = 1e-3, beta = 0.25, gamma = 0.5;
  const double cu = 1, cv = gamma / (beta * h), ca = 1 / (beta * h * h);
  const VecX zero = VecX::Zero(neq);
  VecX r, du, u, v, a;
  SparseMatrix J;

  // Symbolic analysis once (it is reused while the pattern holds).
  sys.evaluate(0, zero, zero, zero, cu, cv, ca, r, &J);
  auto t0 = Clock::now();
  solver->refactorize(J);  // analyses the pattern (and factorises once)
  const double analyse = seconds_since(t0);

  double assembly = 0, factorize = 0, solve = 0, residual = 0;
  double assembly_cpu = 0, factorize_cpu = 0, solve_cpu = 0;
  int steps = 0;
  for (auto _ : state) {
    // From rest at the reference state: predictor u = 0, then Newmark kinematics.
    u = zero;
    for (int it = 0; it < 4; ++it) {
      a = u / (beta * h * h);
      v = gamma / (beta * h) * u;
      t0 = Clock::now();
      double c0 = process_cpu();
      sys.evaluate(h, u, v, a, cu, cv, ca, r, &J);
      assembly += seconds_since(t0);
      assembly_cpu += process_cpu() - c0;
      t0 = Clock::now();
      c0 = process_cpu();
      if (!solver->refactorize(J)) state.SkipWithError("factorisation failed");
      factorize += seconds_since(t0);
      factorize_cpu += process_cpu() - c0;
      t0 = Clock::now();
      c0 = process_cpu();
      if (!solver->solve(-r, du)) state.SkipWithError("solve failed");
      solve += seconds_since(t0);
      solve_cpu += process_cpu() - c0;
      u += du;
    }
    residual = r.norm();
    benchmark::DoNotOptimize(u.data());
    ++steps;
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["dofs"] = neq;
  state.counters["nonzeros"] = static_cast<double>(J.nonZeros());
  state.counters["analyse_s"] = analyse;
  state.counters["assembly_s"] = assembly / steps;
  state.counters["factorize_s"] = factorize / steps;
  state.counters["solve_s"] = solve / steps;
  state.counters["assembly_cpu_s"] = assembly_cpu / steps;
  state.counters["factorize_cpu_s"] = factorize_cpu / steps;
  state.counters["solve_cpu_s"] = solve_cpu / steps;
  state.counters["last_residual"] = residual;
  state.counters["peak_rss_MB"] = static_cast<double>(ru.ru_maxrss) / 1024.0;
  state.SetLabel(std::string(solver->name()));
}

BENCHMARK(BM_ImplicitStep)->Arg(200)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
