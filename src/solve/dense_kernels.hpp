// The dense kernels of the supernodal Cholesky's panels that Eigen does slowly at the panels'
// shapes (tall and narrow; bench/dense_kernels_bench.cpp): the triangular solve of the rows
// below a diagonal block, and the Cholesky factorisation of a wide diagonal block.
// Column-major storage with a column stride; float or double.
#pragma once

#include <cstddef>

namespace velum {

struct OpenBlasKernels;

namespace dense {

/// X := X L⁻ᵀ in place: X is m x w (column j at X + j ldx), L is w x w lower triangular (column
/// j at L + j ldl; only its lower triangle is read) with a nonzero diagonal. Past 160 columns
/// by column blocks, the columns before each block subtracted by a product (OpenBLAS's gemm
/// with `blas`, else gemm_abt below; `blas` is OpenBlasKernels::found()). Deterministic: the same
/// call gives the same bits on any thread.
template <class T>
void solve_lower_transposed(T* X, std::ptrdiff_t ldx, int m, const T* L, std::ptrdiff_t ldl, int w,
                            const OpenBlasKernels* blas);

/// A = L Lᵀ in place (its lower triangle; the upper one is not touched), n x n with column
/// stride lda. Returns -1, or the column whose pivot is not positive (where it stopped), as
/// Eigen's llt_inplace does; like it, a NaN pivot does not stop it. Wide blocks by column
/// blocks: their diagonal blocks by Eigen, the rows below by solve_lower_transposed and the
/// rest of the matrix by a rank update (OpenBLAS's syrk with `blas`, else syrk_lower below).
template <class T>
std::ptrdiff_t cholesky_lower(T* A, std::ptrdiff_t lda, int n, const OpenBlasKernels* blas);

/// C (m x n, column stride ldc) += alpha A Bᵀ, A m x k and B n x k (column strides lda, ldb),
/// by packed blocks and a register-blocked kernel (dense_products.cpp). Each entry's bits
/// depend on k and its own row of A and B only, not on m, n or the entry's place.
template <class T>
void gemm_abt(int m, int n, int k, T alpha, const T* A, std::ptrdiff_t lda, const T* B,
              std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc);

/// C's lower triangle (n x n, its diagonal included) += alpha A Aᵀ, A n x k; the strict upper
/// triangle is not touched. The same kernel and bits as gemm_abt.
template <class T>
void syrk_lower(int n, int k, T alpha, const T* A, std::ptrdiff_t lda, T* C, std::ptrdiff_t ldc);

/// The deepest product the narrow forms below take.
inline constexpr int kNarrowDepth = 256;

/// C (m x n) += A Bᵀ without packing A (dense_products.cpp): the updates of narrow
/// supernodes, where packing A costs as much as the product. Each entry is the same sum as
/// gemm_abt's with alpha = 1, bit for bit; deeper than kNarrowDepth, gemm_abt itself.
template <class T>
void gemm_abt_narrow(int m, int n, int k, const T* A, std::ptrdiff_t lda, const T* B,
                     std::ptrdiff_t ldb, T* C, std::ptrdiff_t ldc);

/// C's lower triangle (n x n, its diagonal included) += A Aᵀ, A n x k, the same way; the
/// strict upper triangle is not touched.
template <class T>
void syrk_lower_narrow(int n, int k, const T* A, std::ptrdiff_t lda, T* C, std::ptrdiff_t ldc);

}  // namespace dense
}  // namespace velum
