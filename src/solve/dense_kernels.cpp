#include "dense_kernels.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>

#include "dense_packets.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace velum::dense {
namespace {

using Eigen::internal::pmadd;
using Eigen::internal::pmul;
using Eigen::internal::pset1;
using Eigen::internal::psub;
using packets::kLanes;
using packets::load;
using packets::Packet;
using packets::store;

// Columns of one call solved directly (wider ones by blocks of kColumns, the columns before a
// block subtracted by a matrix product): past about 160 columns a row block's earlier columns
// no longer stay in L1 while the block is solved (float, m = 800: 100 GF/s at w = 250
// directly, 135 by blocks of 128).
constexpr int kDirectWidth = 160;
constexpr int kColumns = 128;
static_assert(kColumns <= kDirectWidth, "solve_direct's padded rows hold kDirectWidth columns");
// Cholesky of a diagonal block: by Eigen up to this width, by blocks of kColumns beyond.
constexpr int kEigenCholeskyWidth = 192;
// Products without OpenBLAS: dense_products.cpp's for this many rows or more (twice as many
// for the lower triangle's), Eigen's for fewer, where the packing costs more than it saves
// (bench BM_UpdateProduct).
constexpr int kPackedMinRows = 64;

// Rows [0, P · lanes) of X's columns [j0, j0 + C), its columns before j0 solved: for each row
// x_j = (b_j − Σ_{k<j0} x_k L_jk − Σ_{j0<=k<j} x_k L_jk) / L_jj, in that order (first sum by
// fused multiply-adds from zero, the second subtracted term by term), the C P packets in
// registers (C P + P of the vector registers: 32 with P = 3, C = 8 where there are 32, as with
// AVX-512; 16 with C = 4).
template <class T, int P, int C>
inline void solve_block(T* X, std::ptrdiff_t ldx, const T* L, std::ptrdiff_t ldl, int j0) {
  constexpr int S = kLanes<T>;
  Packet<T> acc[C][P];
  packets::clear<T>(acc);
  for (int k = 0; k < j0; ++k) {
    const T* xk = X + k * ldx;
    const T* lk = L + k * ldl + j0;  // L_{j0 + c, k}
    Packet<T> x[P];
#pragma GCC unroll 8
    for (int p = 0; p < P; ++p) x[p] = load(xk + p * S);
#pragma GCC unroll 8
    for (int c = 0; c < C; ++c) {
      const Packet<T> l = pset1<Packet<T>>(lk[c]);
#pragma GCC unroll 8
      for (int p = 0; p < P; ++p) acc[c][p] = pmadd(x[p], l, acc[c][p]);
    }
  }
#pragma GCC unroll 8
  for (int c = 0; c < C; ++c) {
    T* xc = X + (j0 + c) * ldx;
#pragma GCC unroll 8
    for (int p = 0; p < P; ++p) acc[c][p] = psub(load(xc + p * S), acc[c][p]);
#pragma GCC unroll 8
    for (int c2 = 0; c2 < c; ++c2) {
      const Packet<T> l = pset1<Packet<T>>(-L[(j0 + c2) * ldl + j0 + c]);
#pragma GCC unroll 8
      for (int p = 0; p < P; ++p) acc[c][p] = pmadd(acc[c2][p], l, acc[c][p]);
    }
    const Packet<T> inverse = pset1<Packet<T>>(T(1) / L[(j0 + c) * ldl + j0 + c]);
#pragma GCC unroll 8
    for (int p = 0; p < P; ++p) {
      acc[c][p] = pmul(acc[c][p], inverse);  // x_{j0 + c}, for the columns after it
      store(xc + p * S, acc[c][p]);
    }
  }
}

// Rows [0, P · lanes), all w columns: by blocks of eight (with 32 vector registers: 1.5x to 1.9x
// blocks of four from 24 to 150 columns, float, AMD EPYC Zen 5), of four, then one by one.
template <class T, int P>
void solve_rows(T* X, std::ptrdiff_t ldx, const T* L, std::ptrdiff_t ldl, int w) {
  int j = 0;
  if constexpr (EIGEN_ARCH_DEFAULT_NUMBER_OF_REGISTERS >= 32)
    for (; j + 8 <= w; j += 8) solve_block<T, P, 8>(X, ldx, L, ldl, j);
  for (; j + 4 <= w; j += 4) solve_block<T, P, 4>(X, ldx, L, ldl, j);
  for (; j < w; ++j) solve_block<T, P, 1>(X, ldx, L, ldl, j);
}

template <class T>
void solve_direct(T* X, std::ptrdiff_t ldx, int m, const T* L, std::ptrdiff_t ldl, int w) {
  constexpr int S = kLanes<T>;
  int i = 0;
  for (; i + 3 * S <= m; i += 3 * S) solve_rows<T, 3>(X + i, ldx, L, ldl, w);
  for (; i + S <= m; i += S) solve_rows<T, 1>(X + i, ldx, L, ldl, w);
  if (i == m) return;
  // The last rows (fewer than a packet) through a packet's rows padded with zeros: row by
  // row, scalar code would run a few such rows at a fraction of the packets' speed and slow
  // the whole panel. Every row then takes the packets' operations, whichever rows the call
  // holds.
  T pad[S * kDirectWidth];  // solve_direct's widths: up to kDirectWidth, or kColumns
  const int r = m - i;
  for (int j = 0; j < w; ++j)
    for (int k = 0; k < S; ++k) pad[j * S + k] = k < r ? X[i + k + j * ldx] : T(0);
  solve_rows<T, 1>(pad, S, L, ldl, w);
  for (int j = 0; j < w; ++j)
    for (int k = 0; k < r; ++k) X[i + k + j * ldx] = pad[j * S + k];
}

}  // namespace

template <class T>
void solve_lower_transposed(T* X, std::ptrdiff_t ldx, int m, const T* L, std::ptrdiff_t ldl, int w,
                            const OpenBlasKernels* blas) {
  if (m <= 0 || w <= 0) return;
  if (w <= kDirectWidth) return solve_direct(X, ldx, m, L, ldl, w);
  for (int j0 = 0; j0 < w; j0 += kColumns) {
    const int nb = std::min(kColumns, w - j0);
    if (j0 > 0 && blas) {  // X_J −= X_{<J} L_{J,<J}ᵀ
      blas->gemm_abt<T>(m, nb, j0, T(-1), X, static_cast<int>(ldx), L + j0, static_cast<int>(ldl),
                        X + j0 * ldx, static_cast<int>(ldx));
    } else if (j0 > 0 && m >= kPackedMinRows) {
      gemm_abt<T>(m, nb, j0, T(-1), X, ldx, L + j0, ldl, X + j0 * ldx, ldx);
    } else if (j0 > 0) {
      using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
      using Stride = Eigen::OuterStride<>;
      Eigen::Map<Matrix, 0, Stride> XJ(X + j0 * ldx, m, nb, Stride(ldx));
      const Eigen::Map<const Matrix, 0, Stride> before(X, m, j0, Stride(ldx));
      const Eigen::Map<const Matrix, 0, Stride> LJ(L + j0, nb, j0, Stride(ldl));
      XJ.noalias() -= before * LJ.transpose();
    }
    solve_direct(X + j0 * ldx, ldx, m, L + j0 * ldl + j0, ldl, nb);
  }
}

template <class T>
std::ptrdiff_t cholesky_lower(T* A, std::ptrdiff_t lda, int n, const OpenBlasKernels* blas) {
  using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
  using Block = Eigen::Map<Matrix, 0, Eigen::OuterStride<>>;
  const auto block = [&](int i, int j, int rows, int cols) {
    return Block(A + j * lda + i, rows, cols, Eigen::OuterStride<>(lda));
  };
  if (n <= kEigenCholeskyWidth) {
    Block D = block(0, 0, n, n);
    return Eigen::internal::llt_inplace<T, Eigen::Lower>::blocked(D);
  }
  for (int k = 0; k < n; k += kColumns) {
    const int kb = std::min(kColumns, n - k), rest = n - k - kb;
    Block D = block(k, k, kb, kb);
    const Eigen::Index failed = Eigen::internal::llt_inplace<T, Eigen::Lower>::blocked(D);
    if (failed >= 0) return k + failed;
    if (rest == 0) break;
    T* below = A + k * lda + k + kb;
    solve_lower_transposed(below, lda, rest, A + k * lda + k, lda, kb, blas);
    if (blas) {
      blas->syrk_lower<T>(rest, kb, T(-1), below, static_cast<int>(lda), below + kb * lda,
                          static_cast<int>(lda));
    } else if (rest >= 2 * kPackedMinRows) {
      syrk_lower<T>(rest, kb, T(-1), below, lda, below + kb * lda, lda);
    } else {
      const Block B = block(k + kb, k, rest, kb);
      block(k + kb, k + kb, rest, rest)
          .template selfadjointView<Eigen::Lower>()
          .rankUpdate(B, T(-1));
    }
  }
  return -1;
}

template void solve_lower_transposed(double*, std::ptrdiff_t, int, const double*, std::ptrdiff_t,
                                     int, const OpenBlasKernels*);
template void solve_lower_transposed(float*, std::ptrdiff_t, int, const float*, std::ptrdiff_t, int,
                                     const OpenBlasKernels*);
template std::ptrdiff_t cholesky_lower(double*, std::ptrdiff_t, int, const OpenBlasKernels*);
template std::ptrdiff_t cholesky_lower(float*, std::ptrdiff_t, int, const OpenBlasKernels*);

}  // namespace velum::dense
