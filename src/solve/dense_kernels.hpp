// The dense kernels of the supernodal Cholesky's panels that Eigen does slowly at the panels'
// shapes (docs/performance.md, section 27): the triangular solve of the rows below a diagonal
// block, and the Cholesky factorisation of a wide diagonal block. Column-major storage with a
// column stride; float or double.
#pragma once

#include <cstddef>

namespace velum {

struct OpenBlasKernels;

namespace dense {

/// X := X L⁻ᵀ in place: X is m x w (column j at X + j ldx), L is w x w lower triangular (column
/// j at L + j ldl; only its lower triangle is read) with a nonzero diagonal. Past 160 columns
/// by column blocks, the columns before each block subtracted by a product (OpenBLAS's gemm
/// with `blas`, else Eigen's; `blas` is OpenBlasKernels::found()). Deterministic: the same call
/// gives the same bits on any thread.
template <class T>
void solve_lower_transposed(T* X, std::ptrdiff_t ldx, int m, const T* L, std::ptrdiff_t ldl, int w,
                            const OpenBlasKernels* blas);

/// A = L Lᵀ in place (its lower triangle; the upper one is not touched), n x n with column
/// stride lda. Returns -1, or the column whose pivot is not positive (where it stopped), as
/// Eigen's llt_inplace does; like it, a NaN pivot does not stop it. Wide blocks by column
/// blocks: their diagonal blocks by Eigen, the rows below by solve_lower_transposed and the
/// rest of the matrix by a rank update (OpenBLAS's syrk with `blas`, else Eigen's).
template <class T>
std::ptrdiff_t cholesky_lower(T* A, std::ptrdiff_t lda, int n, const OpenBlasKernels* blas);

}  // namespace dense
}  // namespace velum
