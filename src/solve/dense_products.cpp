// The supernodal Cholesky's matrix products (C += alpha A Bᵀ and its lower-triangle form) by
// packed blocks and a register-blocked kernel, for CPUs where no OpenBLAS with kernels of their
// width is loaded: on an AMD EPYC (Zen 5) whose environment sets OPENBLAS_CORETYPE=Haswell,
// Eigen's products and OpenBLAS's Haswell kernels ran the float updates well below what
// 512-bit kernels reach, and these come within a few per cent of those (docs/performance.md).
// The layout is the usual one (Goto and van de Geijn, 2008): B's rows packed by slivers of
// kColumns for a block of kDepth, A's rows by micro-panels of kRows, a micro-panel against a
// sliver held in registers.
#include <Eigen/Core>

#include <algorithm>
#include <vector>

#include "dense_kernels.hpp"
#include "dense_packets.hpp"

namespace velum::dense {
namespace {

using packets::load;
using packets::Packet;
using packets::store;

template <class T>
struct Shape {
  static constexpr int kLanes = packets::kLanes<T>;
  // A micro-tile: three packets of rows by kColumns columns, its accumulators in registers
  // (24 of the 32 vector registers with AVX-512, 12 of 16 with AVX2), with the three packets
  // of A and a broadcast of B.
  static constexpr int kPackets = 3;
  static constexpr int kRows = kPackets * kLanes;
  static constexpr int kColumns = EIGEN_ARCH_DEFAULT_NUMBER_OF_REGISTERS >= 32 ? 8 : 4;
  // The depth of a block (a sliver of B, kColumns x kDepth, stays in L1 while A's micro-panels
  // pass) and A's rows per block (kBlockRows x kDepth in L2: 336 KB).
  static constexpr int kDepth = 256;
  static constexpr int kBlockBytes = 336 * 1024;
  static constexpr int kBlockRows = kRows * (kBlockBytes / (kRows * kDepth * int(sizeof(T))));
  // B's rows per block (its packed block, kDepth x kBlockColumns, in the last-level cache).
  static constexpr int kBlockColumns = 2048;
};

// The packed blocks of one thread, grown to their largest use and kept (nothing allocated
// per call once they have grown).
template <class T>
struct PackedBlocks {
  std::vector<T> a, b;
};

template <class T>
PackedBlocks<T>& packed_blocks() {
  thread_local PackedBlocks<T> blocks;
  return blocks;
}

// Rows [0, rows) of X's columns [0, depth) (column k at X + k ldx), by groups of `group` rows:
// group g at out + g group depth, its row r of column k at k group + r; the last group padded
// with zeros.
template <class T>
void pack(const T* X, std::ptrdiff_t ldx, int rows, int depth, int group, T* out) {
  for (int g = 0; g < rows; g += group) {
    const int n = std::min(group, rows - g);
    for (int k = 0; k < depth; ++k) {
      const T* from = X + k * ldx + g;
      T* to = out + std::ptrdiff_t(g) * depth + std::ptrdiff_t(k) * group;
      std::copy_n(from, n, to);
      std::fill(to + n, to + group, T(0));
    }
  }
}

// acc := Σ_k a_k b_kᵀ over `depth` (from zero, in k's order): P packets of rows of a (column k
// at a + k lda) against kColumns entries of b (b + k kColumns), held in registers.
template <class T, int P>
inline void tile_sum(int depth, const T* a, std::ptrdiff_t lda, const T* b,
                     Packet<T> (&acc)[Shape<T>::kColumns][P]) {
  using Eigen::internal::pmadd;
  using Eigen::internal::pset1;
  constexpr int L = Shape<T>::kLanes, N = Shape<T>::kColumns;
  packets::clear<T>(acc);
  for (int k = 0; k < depth; ++k) {
    Packet<T> x[P];
#pragma GCC unroll 3
    for (int p = 0; p < P; ++p) x[p] = load(a + k * lda + p * L);
#pragma GCC unroll 8
    for (int c = 0; c < N; ++c) {
      const Packet<T> y = pset1<Packet<T>>(b[k * N + c]);
#pragma GCC unroll 3
      for (int p = 0; p < P; ++p) acc[c][p] = pmadd(x[p], y, acc[c][p]);
    }
  }
}

// acc := Σ_k a_k b_kᵀ over one block's depth (from zero, in k's order), then
// C(i, c) += alpha acc(i, c) for the tile's rows [0, rows) and columns [0, cols), and with
// `lower` only where row0 + i >= col0 + c. A whole tile in place; a partial one through a
// zero-padded copy of its columns, with the same packet operations.
template <class T>
void tile(int depth, const T* a, const T* b, T alpha, T* C, std::ptrdiff_t ldc, int rows, int cols,
          bool lower, int row0, int col0) {
  using S = Shape<T>;
  using Eigen::internal::pmadd;
  using Eigen::internal::pset1;
  constexpr int L = S::kLanes, P = S::kPackets, N = S::kColumns;
  Packet<T> acc[N][P];
  tile_sum<T, P>(depth, a, S::kRows, b, acc);
  const Packet<T> scale = pset1<Packet<T>>(alpha);
  const bool whole = rows == S::kRows && cols == N && (!lower || row0 >= col0 + N - 1);
  if (whole) {
#pragma GCC unroll 8
    for (int c = 0; c < N; ++c)
#pragma GCC unroll 3
      for (int p = 0; p < P; ++p) {
        T* to = C + c * ldc + p * L;
        store(to, pmadd(scale, acc[c][p], load(to)));
      }
    return;
  }
  alignas(64) T column[S::kRows];
  for (int c = 0; c < cols; ++c) {
    // Rows from `first` down: all of them, or those on and below the diagonal.
    const int first = lower ? std::clamp(col0 + c - row0, 0, rows) : 0;
    if (first >= rows) continue;
    T* to = C + c * ldc;
    std::fill(column, column + S::kRows, T(0));
    std::copy(to + first, to + rows, column + first);
#pragma GCC unroll 3
    for (int p = 0; p < P; ++p)
      store(column + p * L, pmadd(scale, acc[c][p], load(column + p * L)));
    std::copy(column + first, column + rows, to + first);
  }
}

// C (m x n) += alpha A Bᵀ (A m x k, B n x k), or with `lower` C's entries on and below its
// diagonal only (then A = B, m = n). Each entry of C takes the blocks of kDepth in k's order,
// each block's sum made from zero in k's order: its bits do not depend on m, n or where the
// entry sits in a tile.
template <class T>
void product(int m, int n, int k, T alpha, const T* A, std::ptrdiff_t lda, const T* B,
             std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc, bool lower) {
  using S = Shape<T>;
  if (m <= 0 || n <= 0 || k <= 0) return;
  PackedBlocks<T>& blocks = packed_blocks<T>();
  const auto padded = [](int x, int group) {
    return std::ptrdiff_t((x + group - 1) / group) * group;
  };
  for (int jc = 0; jc < n; jc += S::kBlockColumns) {
    const int nc = std::min(S::kBlockColumns, n - jc);
    // With `lower`, rows above the block's first column add nothing.
    const int i_begin = lower ? jc : 0;
    for (int pc = 0; pc < k; pc += S::kDepth) {
      const int kc = std::min(S::kDepth, k - pc);
      const std::ptrdiff_t b_size = padded(nc, S::kColumns) * kc;
      if (blocks.b.size() < std::size_t(b_size)) blocks.b.resize(std::size_t(b_size));
      pack(B + pc * ldb + jc, ldb, nc, kc, S::kColumns, blocks.b.data());
      for (int ic = i_begin; ic < m; ic += S::kBlockRows) {
        const int mc = std::min(S::kBlockRows, m - ic);
        const std::ptrdiff_t a_size = padded(mc, S::kRows) * kc;
        if (blocks.a.size() < std::size_t(a_size)) blocks.a.resize(std::size_t(a_size));
        pack(A + pc * lda + ic, lda, mc, kc, S::kRows, blocks.a.data());
        for (int jr = 0; jr < nc; jr += S::kColumns) {
          const int j = jc + jr, cols = std::min(S::kColumns, nc - jr);
          const T* b = blocks.b.data() + std::ptrdiff_t(jr) * kc;
          for (int ir = 0; ir < mc; ir += S::kRows) {
            const int i = ic + ir, rows = std::min(S::kRows, mc - ir);
            if (lower && i + rows <= j) continue;  // above the diagonal
            tile(kc, blocks.a.data() + std::ptrdiff_t(ir) * kc, b, alpha, C + j * ldc + i, ldc,
                 rows, cols, lower, i, j);
          }
        }
      }
    }
  }
}

// The narrow products (depth at most kNarrowDepth): B's kColumns rows of a column block are
// copied once (zero past its last column), A is read where it lies, its rows in micro-tiles of
// kRows (or one packet, the last partial packet through a zero-padded copy). Every entry is
// tile()'s sum (tile_sum), from zero in k's order: its bits do not depend on m, n or where the
// entry sits.
//
// C(i, c) += acc(i, c) for rows [0, rows) and columns [0, cols) of a tile at (row0, col0),
// with `lower` only where row0 + i >= col0 + c.
template <class T, int P>
inline void add_tile(const Packet<T> (&acc)[Shape<T>::kColumns][P], T* C, std::ptrdiff_t ldc,
                     int rows, int cols, bool lower, int row0, int col0) {
  constexpr int L = Shape<T>::kLanes, N = Shape<T>::kColumns;
  if (rows == P * L && cols == N && (!lower || row0 >= col0 + N - 1)) {
#pragma GCC unroll 8
    for (int c = 0; c < N; ++c)
#pragma GCC unroll 3
      for (int p = 0; p < P; ++p) {
        T* to = C + c * ldc + p * L;
        store(to, Eigen::internal::padd(load(to), acc[c][p]));
      }
    return;
  }
  // Whole packets at or below the diagonal added as packets, the rest entry by entry.
  alignas(64) T column[L];
  for (int c = 0; c < cols; ++c) {
    const int first = lower ? std::clamp(col0 + c - row0, 0, rows) : 0;
    T* to = C + c * ldc;
#pragma GCC unroll 3
    for (int p = 0; p < P; ++p) {
      const int begin = std::max(first, p * L), end = std::min(rows, (p + 1) * L);
      if (begin >= end) continue;
      if (begin == p * L && end == (p + 1) * L) {
        store(to + p * L, Eigen::internal::padd(load(to + p * L), acc[c][p]));
      } else {
        store(column, acc[c][p]);
        for (int i = begin; i < end; ++i) to[i] += column[i - p * L];
      }
    }
  }
}

template <class T>
void narrow_product(int m, int n, int k, const T* A, std::ptrdiff_t lda, const T* B,
                    std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc, bool lower) {
  using S = Shape<T>;
  constexpr int L = S::kLanes, N = S::kColumns, P = S::kPackets;
  if (m <= 0 || n <= 0 || k <= 0) return;
  // Deeper than the work space below: the packed product (the same bits up to kDepth).
  if (k > kNarrowDepth) return product(m, n, k, T(1), A, lda, B, ldb, C, ldc, lower);
  alignas(64) T b[kNarrowDepth * N];
  alignas(64) T pad[kNarrowDepth * L];
  Packet<T> acc[N][P];
  Packet<T> one[N][1];
  for (int j = 0; j < n; j += N) {
    const int cols = std::min(N, n - j);
    for (int q = 0; q < k; ++q)
      for (int c = 0; c < N; ++c) b[q * N + c] = c < cols ? B[q * ldb + j + c] : T(0);
    int i = lower ? j : 0;
    for (; i + P * L <= m; i += P * L) {
      tile_sum<T, P>(k, A + i, lda, b, acc);
      add_tile<T, P>(acc, C + j * ldc + i, ldc, P * L, cols, lower, i, j);
    }
    for (; i + L <= m; i += L) {
      tile_sum<T, 1>(k, A + i, lda, b, one);
      add_tile<T, 1>(one, C + j * ldc + i, ldc, L, cols, lower, i, j);
    }
    if (i < m) {  // the last rows, fewer than a packet, through a zero-padded copy
      const int rows = m - i;
      for (int q = 0; q < k; ++q)
        for (int r = 0; r < L; ++r) pad[q * L + r] = r < rows ? A[q * lda + i + r] : T(0);
      tile_sum<T, 1>(k, pad, L, b, one);
      add_tile<T, 1>(one, C + j * ldc + i, ldc, rows, cols, lower, i, j);
    }
  }
}

}  // namespace

template <class T>
void gemm_abt_narrow(int m, int n, int k, const T* A, std::ptrdiff_t lda, const T* B,
                     std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc) {
  narrow_product(m, n, k, A, lda, B, ldb, C, ldc, false);
}

template <class T>
void syrk_lower_narrow(int n, int k, const T* A, std::ptrdiff_t lda, T* C, std::ptrdiff_t ldc) {
  narrow_product(n, n, k, A, lda, A, lda, C, ldc, true);
}

template <class T>
void gemm_abt(int m, int n, int k, T alpha, const T* A, std::ptrdiff_t lda, const T* B,
              std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc) {
  product(m, n, k, alpha, A, lda, B, ldb, C, ldc, false);
}

template <class T>
void syrk_lower(int n, int k, T alpha, const T* A, std::ptrdiff_t lda, T* C, std::ptrdiff_t ldc) {
  product(n, n, k, alpha, A, lda, A, lda, C, ldc, true);
}

template void gemm_abt(int, int, int, double, const double*, std::ptrdiff_t, const double*,
                       std::ptrdiff_t, double*, std::ptrdiff_t);
template void gemm_abt(int, int, int, float, const float*, std::ptrdiff_t, const float*,
                       std::ptrdiff_t, float*, std::ptrdiff_t);
template void syrk_lower(int, int, double, const double*, std::ptrdiff_t, double*, std::ptrdiff_t);
template void syrk_lower(int, int, float, const float*, std::ptrdiff_t, float*, std::ptrdiff_t);
template void gemm_abt_narrow(int, int, int, const double*, std::ptrdiff_t, const double*,
                              std::ptrdiff_t, double*, std::ptrdiff_t);
template void gemm_abt_narrow(int, int, int, const float*, std::ptrdiff_t, const float*,
                              std::ptrdiff_t, float*, std::ptrdiff_t);
template void syrk_lower_narrow(int, int, const double*, std::ptrdiff_t, double*, std::ptrdiff_t);
template void syrk_lower_narrow(int, int, const float*, std::ptrdiff_t, float*, std::ptrdiff_t);

}  // namespace velum::dense
