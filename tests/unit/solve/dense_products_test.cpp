// dense_products.cpp's packed products against their definitions, in float and double, at
// shapes that reach whole and partial tiles, several blocks of depth, rows and columns, and
// strides larger than the rows; the lower-triangle form leaves the strict upper triangle and
// the spare rows alone; an entry's bits do not depend on the call that holds it (the supernodal
// Cholesky's one-thread and two-thread factorisations split the same update differently); the
// narrow products without packing likewise, to the packed products' bits.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <limits>

#include "solve/dense_kernels.hpp"
#include "solve/dense_packets.hpp"

namespace velum {
namespace {

template <class T>
using DenseMatrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

// |computed − exact| within (k + 2) eps (|before| + |A| |B|ᵀ) entry by entry, the exact
// before + alpha A Bᵀ in long double from the same rounded inputs; with `lower`, the entries on
// and below the diagonal only.
template <class T>
void expect_close(const DenseMatrix<T>& computed, const DenseMatrix<T>& before, T alpha,
                  const DenseMatrix<T>& A, const DenseMatrix<T>& B, int k, bool lower = false) {
  using Wide = DenseMatrix<long double>;
  const Wide exact = before.template cast<long double>() +
                     static_cast<long double>(alpha) * (A.template cast<long double>() *
                                                        B.template cast<long double>().transpose());
  const Wide scale = before.template cast<long double>().cwiseAbs() +
                     A.template cast<long double>().cwiseAbs() *
                         B.template cast<long double>().cwiseAbs().transpose();
  const long double eps = std::numeric_limits<T>::epsilon();
  for (Eigen::Index j = 0; j < computed.cols(); ++j)
    for (Eigen::Index i = lower ? j : 0; i < computed.rows(); ++i)
      ASSERT_LE(std::abs(static_cast<long double>(computed(i, j)) - exact(i, j)),
                (k + 2) * eps * scale(i, j))
          << i << ", " << j;
}

template <class T>
void check_gemm(int m, int n, int k, T alpha) {
  SCOPED_TRACE(testing::Message() << "m = " << m << ", n = " << n << ", k = " << k << ", "
                                  << (sizeof(T) == 4 ? "float" : "double"));
  // Column strides larger than the rows (as in the panels): A and B inside taller matrices.
  const DenseMatrix<T> A_store = DenseMatrix<T>::Random(m + 3, k),
                       B_store = DenseMatrix<T>::Random(n + 5, k);
  DenseMatrix<T> C_store = DenseMatrix<T>::Random(m + 2, n);
  const DenseMatrix<T> C_before = C_store;
  dense::gemm_abt<T>(m, n, k, alpha, A_store.data() + 1, m + 3, B_store.data() + 2, n + 5,
                     C_store.data(), m + 2);
  expect_close<T>(C_store.topRows(m), C_before.topRows(m), alpha, A_store.middleRows(1, m),
                  B_store.middleRows(2, n), k);
  EXPECT_TRUE(C_store.bottomRows(2) == C_before.bottomRows(2));  // spare rows not written
}

TEST(DenseProducts, GemmAgainstItsDefinition) {
  const int shapes[][3] = {{1, 1, 1},      {7, 3, 5},      {48, 8, 16},   {49, 9, 17},
                           {47, 7, 256},   {100, 33, 257}, {337, 50, 64}, {700, 20, 600},
                           {30, 2100, 40}, {1, 100, 3}};
  for (const auto& s : shapes) {
    check_gemm<float>(s[0], s[1], s[2], 1.0f);
    check_gemm<float>(s[0], s[1], s[2], -1.0f);
    check_gemm<double>(s[0], s[1], s[2], 1.0);
    check_gemm<double>(s[0], s[1], s[2], -1.0);
  }
}

template <class T>
void check_syrk(int n, int k, T alpha) {
  SCOPED_TRACE(testing::Message() << "n = " << n << ", k = " << k << ", "
                                  << (sizeof(T) == 4 ? "float" : "double"));
  const DenseMatrix<T> A_store = DenseMatrix<T>::Random(n + 4, k);
  DenseMatrix<T> C_store = DenseMatrix<T>::Random(n + 3, n);
  const DenseMatrix<T> C_before = C_store;
  dense::syrk_lower<T>(n, k, alpha, A_store.data() + 4, n + 4, C_store.data(), n + 3);
  // The strict upper triangle untouched; the lower one (with the diagonal) the product.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) ASSERT_EQ(C_store(i, j), C_before(i, j)) << i << ", " << j;
  const DenseMatrix<T> A = A_store.bottomRows(n);
  expect_close<T>(C_store.topRows(n), C_before.topRows(n), alpha, A, A, k, true);
  EXPECT_TRUE(C_store.bottomRows(3) == C_before.bottomRows(3));
}

TEST(DenseProducts, LowerTriangleAgainstItsDefinition) {
  for (const auto& [n, k] : {std::pair{1, 1},
                             {5, 3},
                             {8, 8},
                             {47, 9},
                             {48, 64},
                             {49, 65},
                             {200, 300},
                             {345, 40},
                             {2100, 12}}) {
    check_syrk<float>(n, k, 1.0f);
    check_syrk<double>(n, k, -1.0);
  }
}

// An entry's bits depend on its rows of A and B and on k alone: a product cut into pieces of
// rows and columns (and the lower-triangle form cut into a square and the rectangle below, as
// SupernodalCholesky::update_columns does) gives the whole call's bits.
TEST(DenseProducts, EntriesIndependentOfTheCall) {
  const int m = 461, k = 300;
  const DenseMatrix<float> A = DenseMatrix<float>::Random(m, k);
  DenseMatrix<float> whole = DenseMatrix<float>::Zero(m, m);
  dense::syrk_lower<float>(m, k, 1.0f, A.data(), m, whole.data(), m);
  DenseMatrix<float> pieces = DenseMatrix<float>::Zero(m, m);
  for (const auto& [begin, end] : {std::pair{0, 5}, {5, 53}, {53, 200}, {200, m}}) {
    const int cols = end - begin, below = m - end;
    dense::syrk_lower<float>(cols, k, 1.0f, A.data() + begin, m, pieces.data() + begin * m + begin,
                             m);
    dense::gemm_abt<float>(below, cols, k, 1.0f, A.data() + end, m, A.data() + begin, m,
                           pieces.data() + begin * m + end, m);
  }
  EXPECT_TRUE(whole == pieces);
}

// The narrow products (no packing, depth up to kNarrowDepth) against their definitions, with
// the same guarantees: spare rows and the strict upper triangle untouched, every packet tail;
// and each entry the packed product's bits (alpha = 1), whole or cut as update_columns cuts.
template <class T>
void check_narrow(int m, int n, int k) {
  SCOPED_TRACE(testing::Message() << "m = " << m << ", n = " << n << ", k = " << k << ", "
                                  << (sizeof(T) == 4 ? "float" : "double"));
  const DenseMatrix<T> A_store = DenseMatrix<T>::Random(m + 3, k),
                       B_store = DenseMatrix<T>::Random(n + 5, k);
  DenseMatrix<T> C_store = DenseMatrix<T>::Random(m + 2, n);
  const DenseMatrix<T> C_before = C_store;
  dense::gemm_abt_narrow<T>(m, n, k, A_store.data() + 1, m + 3, B_store.data() + 2, n + 5,
                            C_store.data(), m + 2);
  expect_close<T>(C_store.topRows(m), C_before.topRows(m), T(1), A_store.middleRows(1, m),
                  B_store.middleRows(2, n), k);
  EXPECT_TRUE(C_store.bottomRows(2) == C_before.bottomRows(2));
  DenseMatrix<T> packed = C_before;
  dense::gemm_abt<T>(m, n, k, T(1), A_store.data() + 1, m + 3, B_store.data() + 2, n + 5,
                     packed.data(), m + 2);
  EXPECT_TRUE(packed == C_store);
  // The lower-triangle form, n x n.
  DenseMatrix<T> L_store = DenseMatrix<T>::Random(n + 3, n);
  const DenseMatrix<T> L_before = L_store;
  dense::syrk_lower_narrow<T>(n, k, B_store.data() + 2, n + 5, L_store.data(), n + 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) ASSERT_EQ(L_store(i, j), L_before(i, j)) << i << ", " << j;
  const DenseMatrix<T> B = B_store.middleRows(2, n);
  expect_close<T>(L_store.topRows(n), L_before.topRows(n), T(1), B, B, k, true);
  EXPECT_TRUE(L_store.bottomRows(3) == L_before.bottomRows(3));
  DenseMatrix<T> L_packed = L_before;
  dense::syrk_lower<T>(n, k, T(1), B_store.data() + 2, n + 5, L_packed.data(), n + 3);
  EXPECT_TRUE(L_packed == L_store);
}

TEST(DenseProducts, NarrowProductsAgainstTheirDefinitionAndThePackedBits) {
  const int shapes[][3] = {{1, 1, 1},
                           {5, 3, 3},
                           {15, 9, 9},
                           {16, 8, 12},
                           {17, 7, 15},
                           {47, 16, 24},
                           {48, 17, 48},
                           {49, 60, 64},
                           {100, 9, 1},
                           {130, 33, 96},
                           {63, 200, 200},
                           {250, 100, dense::kNarrowDepth},
                           {70, 30, dense::kNarrowDepth + 5}};  // deeper: the packed product
  for (const auto& s : shapes) {
    check_narrow<float>(s[0], s[1], s[2]);
    check_narrow<double>(s[0], s[1], s[2]);
  }
  // Cut as SupernodalCholesky::update_columns cuts an update: the whole call's bits.
  const int m = 173, k = 24;
  const DenseMatrix<float> A = DenseMatrix<float>::Random(m, k);
  DenseMatrix<float> whole = DenseMatrix<float>::Zero(m, m),
                     pieces = DenseMatrix<float>::Zero(m, m);
  dense::syrk_lower_narrow<float>(m, k, A.data(), m, whole.data(), m);
  for (const auto& [begin, end] : {std::pair{0, 5}, {5, 53}, {53, 100}, {100, m}}) {
    const int cols = end - begin, below = m - end;
    dense::syrk_lower_narrow<float>(cols, k, A.data() + begin, m, pieces.data() + begin * m + begin,
                                    m);
    dense::gemm_abt_narrow<float>(below, cols, k, A.data() + end, m, A.data() + begin, m,
                                  pieces.data() + begin * m + end, m);
  }
  EXPECT_TRUE(whole == pieces);
}

// A partial packet: its first n entries read and written, nothing past them (a masked vector on
// AVX-512, where a stray lane would overwrite a neighbouring panel's values).
template <class T>
void check_partial_packets() {
  namespace packets = dense::packets;
  constexpr int L = packets::kLanes<T>;
  for (int n = 1; n < L; ++n) {
    T from[2 * L], to[2 * L], lanes[L];
    for (int i = 0; i < 2 * L; ++i) from[i] = T(i + 1), to[i] = T(-7);
    const auto x = packets::load_first(from, n);
    packets::store(lanes, x);
    packets::store_first(to, x, n);
    for (int i = 0; i < L; ++i) EXPECT_EQ(lanes[i], i < n ? from[i] : T(0)) << n << " " << i;
    for (int i = 0; i < 2 * L; ++i) EXPECT_EQ(to[i], i < n ? from[i] : T(-7)) << n << " " << i;
  }
}

TEST(DensePackets, PartialPacketsReadAndWriteTheirEntriesOnly) {
  check_partial_packets<float>();
  check_partial_packets<double>();
}

}  // namespace
}  // namespace velum
