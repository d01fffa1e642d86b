// The supernodal Cholesky with float panels and iterative refinement in double (kMixed) against
// double panels, on one thread (pin it: taskset -c 0). Matrices (first argument): 0 the
// pressurised square's K + M (well conditioned), 1 the clamped square domed by a tenth of its
// side, its stiffness K at rest (a stress-free membrane: in-plane stiffness only, out of plane
// through the curvature), 2 the stiffness at rest of the model file named by VELUM_MODEL (the
// Hencky dome of bench/compare-fenicsx, for instance; skipped without it), or of a dynamic model
// its first step's Jacobian cu K + ca M with its integrator's coefficients (K + 4 M / Δt² for
// the trapezoidal Newmark of the 1M-equation square of `compare-ccx --scaling`, for instance).
// Second argument: elements per side (0 and 1); third: 0 double, 1 mixed. Time per factorisation;
// counters: `solve_ms` (the best of five solves, refinement included), `pass_ms` (the best of five
// passes of the factor alone: solve_within with an infinite residual), `backward_error`
// (‖b − A x‖∞ / (‖A‖∞ ‖x‖∞)), `float_solves` per solve, `fallbacks` to the double
// factor, `gflops` of the factorisation.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>

#include "model_jacobian.hpp"
#include "solve/supernodal_cholesky.hpp"
#include "square_membrane.hpp"

namespace {

using namespace velum;
// The matrix `which` (above), or an empty one when VELUM_MODEL is not set.
SparseMatrix matrix(int which, int n) {
  if (which == 2) {
    const char* file = std::getenv("VELUM_MODEL");
    return file ? bench::model_jacobian(file) : SparseMatrix();
  }
  const std::unique_ptr<Model> model = which == 0 ? pressurised_square(n) : clamped_square(n, 0.1);
  MechanicalSystem sys(*model);
  VecX u = VecX::Zero(sys.size()), v = u, a = u, r;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, 1.0, 0.0, which == 0 ? 1.0 : 0.0, r, &J);
  return J;
}

void BM_MixedCholesky(benchmark::State& state) {
  omp_set_num_threads(1);
  const SparseMatrix A = matrix(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  if (A.rows() == 0) {
    state.SkipWithError("VELUM_MODEL names no model file");
    return;
  }
  const auto precision = state.range(2) == 1 ? SupernodalCholesky::Precision::kMixed
                                             : SupernodalCholesky::Precision::kDouble;
  SupernodalCholesky chol({}, SupernodalCholesky::kSplitFlops, precision);
  if (!chol.analyze(A)) {
    state.SkipWithError("analysis failed");
    return;
  }
  for (auto _ : state) {
    if (!chol.factorize(A)) {
      state.SkipWithError(("factorisation failed: " + chol.status()).c_str());
      return;
    }
  }
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 2.0);
  Eigen::VectorXd x;
  double best = std::numeric_limits<double>::infinity();
  const long solves_before = chol.mixed_counts().float_solves;
  for (int k = 0; k < 5; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!chol.solve(b, x)) {
      state.SkipWithError("solve failed");
      return;
    }
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  // One pass of the factor alone (forward and back, no residual): what memory bandwidth sets.
  double pass = std::numeric_limits<double>::infinity();
  Eigen::VectorXd xp;
  for (int k = 0; k < 5; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    chol.solve_within(b, xp, std::numeric_limits<double>::infinity());
    pass = std::min(pass,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  Eigen::VectorXd r = b - A * x;
  double norm = 0;  // ‖A‖∞
  for (int j = 0; j < A.outerSize(); ++j) norm = std::max(norm, A.col(j).cwiseAbs().sum());
  state.counters["solve_ms"] = 1e3 * best;
  state.counters["pass_ms"] = 1e3 * pass;
  state.counters["backward_error"] =
      r.lpNorm<Eigen::Infinity>() / (norm * x.lpNorm<Eigen::Infinity>());
  state.counters["float_solves"] = double(chol.mixed_counts().float_solves - solves_before) / 5;
  state.counters["fallbacks"] = static_cast<double>(chol.mixed_counts().double_fallbacks);
  state.counters["float_factor"] = chol.float_factor();
  state.counters["dofs"] = static_cast<double>(A.rows());
  state.counters["float_factor_mb"] = chol.structure().values * 4e-6;
  state.counters["supernodes"] = chol.structure().supernodes();
  state.counters["gflops"] = benchmark::Counter(chol.structure().flops * 1e-9,
                                                benchmark::Counter::kIsIterationInvariantRate);
  omp_set_num_threads(omp_get_num_procs());
}
BENCHMARK(BM_MixedCholesky)
    ->ArgsProduct({{0, 1}, {100, 200}, {0, 1}})
    ->Args({2, 0, 0})
    ->Args({2, 0, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
