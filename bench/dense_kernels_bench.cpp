// The supernodal Cholesky's dense kernels (src/solve/dense_kernels.hpp) against Eigen's, at
// panel shapes the factorisations meet (rows below x width), and its updates' product. Pin to one
// core (taskset -c 0); OPENBLAS_CORETYPE=SkylakeX on an AVX-512 CPU gives the blocked Cholesky
// OpenBLAS's syrk, as the velum command does. Arguments: rows, width, 0 Eigen / 1 Velum's kernel /
// 2 neither (the copy that restores the input before each call, timed with it: subtract it; pausing
// the timer costs more than a narrow block's factorisation).
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "random_spd.hpp"
#include "solve/dense_kernels.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace {

using velum::OpenBlasKernels;
using velum::random_spd;

template <class T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <class T>
using Panel = Eigen::Map<Matrix<T>, 0, Eigen::OuterStride<>>;

// One call per iteration after the input is restored (`reset`): Velum's kernel (third argument
// 1, or 3 for a second form of it), Eigen's (0) or neither (2: the restoring copy alone, to
// subtract), on one thread.
template <class Reset, class Ours, class Eigens>
void time_calls(benchmark::State& state, const Reset& reset, const Ours& ours,
                const Eigens& eigens) {
  velum::SerialOpenBlas serial(OpenBlasKernels::loaded());
  const auto variant = state.range(2);
  for (auto _ : state) {
    reset();
    if (variant == 1 || variant == 3)
      ours();
    else if (variant == 0)
      eigens();
  }
}

// X := X L⁻ᵀ on the rows below a panel's diagonal block (column stride w + m).
template <class T>
void BM_PanelTriangularSolve(benchmark::State& state) {
  const int m = static_cast<int>(state.range(0)), w = static_cast<int>(state.range(1));
  const int ld = w + m;
  Matrix<T> panel = Matrix<T>::Random(ld, w);
  panel.topRows(w) = random_spd<T>(w).llt().matrixL();
  const Matrix<T> start = panel;
  time_calls(
      state, [&] { panel = start; },
      [&] {
        velum::dense::solve_lower_transposed(panel.data() + w, ld, m, panel.data(), ld, w,
                                             OpenBlasKernels::found());
        benchmark::DoNotOptimize(panel.data());
      },
      [&] {
        const Panel<T> D(panel.data(), w, w, Eigen::OuterStride<>(ld));
        Panel<T> X(panel.data() + w, m, w, Eigen::OuterStride<>(ld));
        D.template triangularView<Eigen::Lower>()
            .transpose()
            .template solveInPlace<Eigen::OnTheRight>(X);
        benchmark::DoNotOptimize(panel.data());
      });
  state.counters["gflops"] =
      benchmark::Counter(double(m) * w * w * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

// The Cholesky of a diagonal block of width n (column stride n + 64, as in a panel).
template <class T>
void BM_DiagonalCholesky(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int ld = n + 64;
  Matrix<T> block = Matrix<T>::Zero(ld, n);
  block.topRows(n) = random_spd<T>(n);
  const Matrix<T> start = block;
  time_calls(
      state, [&] { block = start; },
      [&] {
        benchmark::DoNotOptimize(
            velum::dense::cholesky_lower(block.data(), ld, n, OpenBlasKernels::found()));
      },
      [&] {
        Panel<T> D(block.data(), n, n, Eigen::OuterStride<>(ld));
        benchmark::DoNotOptimize(Eigen::internal::llt_inplace<T, Eigen::Lower>::blocked(D));
      });
  state.counters["gflops"] = benchmark::Counter(double(n) * n * n / 3 * 1e-9,
                                                benchmark::Counter::kIsIterationInvariantRate);
}

// An update's lower triangle W += Lb Lbᵀ (Lb the m rows below a panel of width w, column
// stride w + m), as SupernodalCholesky::scatter_update makes it where no OpenBLAS with AVX-512
// kernels is loaded: dense_products.cpp's packed product (third argument 1), its narrow
// product without packing (3, up to kNarrowDepth columns) against Eigen's (0).
template <class T>
void BM_UpdateProduct(benchmark::State& state) {
  const int m = static_cast<int>(state.range(0)), w = static_cast<int>(state.range(1));
  const Matrix<T> panel = Matrix<T>::Random(w + m, w);
  Matrix<T> W = Matrix<T>::Zero(m, m);  // accumulates: nothing to restore
  const bool narrow = state.range(2) == 3;
  if (narrow && w > velum::dense::kNarrowDepth) {
    state.SkipWithError("deeper than the narrow product takes");
    return;
  }
  time_calls(
      state, [] {},
      [&] {
        if (narrow)
          velum::dense::syrk_lower_narrow<T>(m, w, panel.data() + w, w + m, W.data(), m);
        else
          velum::dense::syrk_lower<T>(m, w, T(1), panel.data() + w, w + m, W.data(), m);
        benchmark::DoNotOptimize(W.data());
      },
      [&] {
        const Eigen::Map<const Matrix<T>, 0, Eigen::OuterStride<>> Lb(panel.data() + w, m, w,
                                                                      Eigen::OuterStride<>(w + m));
        W.template triangularView<Eigen::Lower>() += Lb * Lb.transpose();
        benchmark::DoNotOptimize(W.data());
      });
  state.counters["gflops"] = benchmark::Counter(double(m) * (m + 1) * w * 1e-9,
                                                benchmark::Counter::kIsIterationInvariantRate);
}

void update_shapes(benchmark::internal::Benchmark* b) {
  for (const auto& [m, w] : {std::pair{100, 64},
                             {300, 64},
                             {600, 96},
                             {1000, 150},
                             {1500, 300},
                             {2500, 600},
                             {1700, 1700}})
    for (const int ours : {0, 1}) b->Args({m, w, ours});
  // The narrow supernodes of a membrane's factor (most of them 9 to 16 columns wide).
  for (const auto& [m, w] : {std::pair{20, 3},
                             {40, 9},
                             {60, 12},
                             {100, 15},
                             {130, 24},
                             {200, 48},
                             {100, 64},
                             {300, 64},
                             {150, 96},
                             {250, 150},
                             {200, 250}})
    for (const int ours : {0, 1, 3}) b->Args({m, w, ours});
}

void panel_shapes(benchmark::internal::Benchmark* b) {
  for (const auto& [m, w] : {std::pair{60, 6},
                             {100, 12},
                             {150, 24},
                             {200, 48},
                             {300, 96},
                             {500, 150},
                             {800, 250},
                             {1500, 500},
                             {1700, 1700},
                             {96, 1700}})
    for (const int ours : {0, 1, 2}) b->Args({m, w, ours});
}

void block_widths(benchmark::internal::Benchmark* b) {
  for (const int n : {6, 12, 24, 96, 192, 400, 800, 1700})
    for (const int ours : {0, 1, 2}) b->Args({n, 0, ours});
}

BENCHMARK(BM_PanelTriangularSolve<float>)->Apply(panel_shapes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PanelTriangularSolve<double>)->Apply(panel_shapes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiagonalCholesky<float>)->Apply(block_widths)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DiagonalCholesky<double>)->Apply(block_widths)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_UpdateProduct<float>)->Apply(update_shapes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_UpdateProduct<double>)->Apply(update_shapes)->Unit(benchmark::kMicrosecond);

}  // namespace
