// The supernodal Cholesky's dense kernels (dense_kernels.hpp) against Eigen's, in float and
// double, at widths and row counts that reach each path: the packet blocks of three and one
// packet, the padded last rows, the row-by-row last rows of wide calls, the column blocks past
// 160 columns, and the blocked Cholesky past 192 (with OpenBLAS's syrk where it is used).
#include "solve/dense_kernels.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "random_spd.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace velum {
namespace {

template <class T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

template <class T>
void check_solve(int m, int w, const OpenBlasKernels* blas) {
  SCOPED_TRACE(testing::Message() << "m = " << m << ", w = " << w << ", "
                                  << (sizeof(T) == 4 ? "float" : "double")
                                  << (blas ? ", OpenBLAS" : ""));
  // A panel as the factorisation holds it: L11 on top of the rows below, column stride w + m,
  // here with spare rows so that the stride is not the rows' count.
  const int ld = w + m + 3;
  Matrix<T> panel = Matrix<T>::Random(ld, w);
  const Matrix<T> L = random_spd<T>(w).llt().matrixL();
  panel.topRows(w) = L;
  panel.topRows(w).template triangularView<Eigen::StrictlyUpper>().setConstant(T(7));  // unread
  const Matrix<T> B = panel.middleRows(w, m), spare = panel.bottomRows(3);
  dense::solve_lower_transposed(panel.data() + w, ld, m, panel.data(), ld, w, blas);
  const Matrix<T> X = panel.middleRows(w, m);
  // X Lᵀ = B to the precision's round-off, relative to |X| |L|ᵀ.
  const Matrix<T> residual = X * L.transpose() - B;
  const Matrix<T> scale = X.cwiseAbs() * L.cwiseAbs().transpose();
  const T eps = std::numeric_limits<T>::epsilon();
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < m; ++i)
      ASSERT_LE(std::abs(residual(i, j)), T(4) * (w + 1) * eps * scale(i, j)) << i << ", " << j;
  // The spare rows below are not written.
  EXPECT_TRUE(panel.bottomRows(3) == spare);
}

TEST(DenseKernels, TriangularSolveAgainstItsDefinition) {
  const int shapes[][2] = {{1, 1},     {5, 3},     {30, 3},   {47, 6},   {48, 12},  {49, 13},
                           {100, 12},  {150, 24},  {200, 48}, {300, 96}, {17, 129}, {61, 160},
                           {300, 161}, {333, 250}, {97, 400}, {40, 300}};
  const OpenBlasKernels* blas = OpenBlasKernels::found();
  for (const auto& s : shapes) {
    check_solve<float>(s[0], s[1], nullptr);
    check_solve<double>(s[0], s[1], nullptr);
    if (blas) {
      check_solve<float>(s[0], s[1], blas);
      check_solve<double>(s[0], s[1], blas);
    }
  }
}

// Up to 160 columns each row's result does not depend on the rows a call is given (the last
// rows, padded to a packet, take the packets' operations bit for bit).
TEST(DenseKernels, TriangularSolveRowsIndependentOfTheCall) {
  for (const int w : {3, 12, 50, 130, 160}) {
    const int m = 131, ld = w + m;
    Matrix<double> panel = Matrix<double>::Random(ld, w);
    panel.topRows(w) = random_spd<double>(w).llt().matrixL();
    Matrix<double> whole = panel, pieces = panel;
    dense::solve_lower_transposed(whole.data() + w, ld, m, whole.data(), ld, w, nullptr);
    for (const auto& [begin, end] : {std::pair{0, 7}, std::pair{7, 64}, std::pair{64, m}})
      dense::solve_lower_transposed(pieces.data() + w + begin, ld, end - begin, pieces.data(), ld,
                                    w, nullptr);
    EXPECT_TRUE(whole == pieces) << "w = " << w;
  }
}

template <class T>
void check_cholesky(int n, const OpenBlasKernels* blas) {
  SCOPED_TRACE(testing::Message() << "n = " << n << ", " << (sizeof(T) == 4 ? "float" : "double")
                                  << (blas ? ", OpenBLAS" : ""));
  const Matrix<T> A = random_spd<T>(n);
  const int ld = n + 5;
  Matrix<T> work = Matrix<T>::Constant(ld, n, T(3));
  work.topRows(n) = A;
  work.topRows(n).template triangularView<Eigen::StrictlyUpper>().setConstant(T(9));
  ASSERT_EQ(dense::cholesky_lower(work.data(), ld, n, blas), -1);
  const Matrix<T> L = work.topRows(n).template triangularView<Eigen::Lower>();
  const T error = (L * L.transpose() - A).cwiseAbs().maxCoeff();
  EXPECT_LE(error, T(8) * n * std::numeric_limits<T>::epsilon() * A.cwiseAbs().maxCoeff());
  // Only the lower triangle is written.
  EXPECT_TRUE(
      (work.topRows(n).template triangularView<Eigen::StrictlyUpper>().toDenseMatrix().array() ==
       T(9))
          .count() == n * (n - 1) / 2);
  EXPECT_TRUE((work.bottomRows(5).array() == T(3)).all());
}

TEST(DenseKernels, CholeskyFactorsWideAndNarrowBlocks) {
  const OpenBlasKernels* blas = OpenBlasKernels::found();
  for (const int n : {1, 3, 7, 8, 9, 12, 16, 17, 31, 32, 33, 192, 193, 300, 520}) {
    check_cholesky<float>(n, nullptr);
    check_cholesky<double>(n, nullptr);
    if (blas) {
      check_cholesky<float>(n, blas);
      check_cholesky<double>(n, blas);
    }
  }
}

// A pivot that is not positive stops the factorisation at its column, in the first column
// block or a later one, as Eigen's llt_inplace reports it.
TEST(DenseKernels, CholeskyReportsTheFirstColumnNotPositive) {
  for (const auto& [n, bad] : {std::pair{300, 5}, {300, 150}, {300, 260}, {12, 4}, {30, 29}}) {
    Matrix<double> A = random_spd<double>(n);
    // Column `bad` made a copy of column `bad − 1` (row and column): the matrix is singular
    // there and the pivot of column `bad` is zero to round-off, or negative with the shift.
    A.row(bad) = A.row(bad - 1);
    A.col(bad) = A.col(bad - 1);
    A(bad, bad) -= 1e-3;
    Matrix<double> work = A;
    EXPECT_EQ(dense::cholesky_lower(work.data(), n, n, nullptr), bad);
  }
}

// A NaN pivot does not stop it (as Eigen's does not): the caller reads the diagonal.
TEST(DenseKernels, CholeskyCarriesANanPivotThrough) {
  for (const int n : {12, 30, 300}) {
    Matrix<double> A = random_spd<double>(n);
    A(3, 3) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(dense::cholesky_lower(A.data(), n, n, nullptr), -1) << n;
    EXPECT_TRUE(std::isnan(A(3, 3))) << n;
  }
}

}  // namespace
}  // namespace velum
