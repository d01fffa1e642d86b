#include "supernodal_cholesky.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ordering.hpp"

namespace velum {
namespace {

using Panel = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using Segment = Eigen::Map<Eigen::VectorXd>;

}  // namespace

bool SupernodalCholesky::analyze(const SparseMatrix& A) {
  factorized_ = false;
  st_ = analyse_supernodes(A, nested_dissection(A), relax_, Factor::kCholesky);
  values_.assign(static_cast<std::size_t>(st_.values), 0.0);
  update_.assign(static_cast<std::size_t>(st_.most_below) * st_.most_below, 0.0);
  gather_.assign(static_cast<std::size_t>(std::max(st_.most_below, 1)), 0.0);
  y_.assign(static_cast<std::size_t>(st_.n), 0.0);
  status_.clear();
  return true;
}

bool SupernodalCholesky::factorize(const SparseMatrix& A) {
  factorized_ = false;
  if (A.rows() != st_.n || A.nonZeros() != static_cast<Eigen::Index>(st_.entry.size())) {
    status_ = "supernodal Cholesky: the matrix does not have the analysed pattern";
    return false;
  }
  SerialEigen serial;
  std::fill(values_.begin(), values_.end(), 0.0);
  const double* a = A.valuePtr();
  for (std::size_t k = 0; k < st_.entry.size(); ++k)
    if (const std::ptrdiff_t e = st_.entry[k]; e >= 0) values_[e] = a[k];
  smallest_pivot_ = std::numeric_limits<double>::infinity();
  largest_pivot_ = 0;
  for (int s = 0; s < st_.supernodes(); ++s) {
    if (!factor_supernode(s)) return false;
    scatter_update(s);
  }
  pivot_ratio_ = smallest_pivot_ / largest_pivot_;
  if (!(pivot_ratio_ >= kSmallestPivotRatio)) {
    status_ =
        fmt::format("supernodal Cholesky: pivots span {:.1e} (nearly singular)", pivot_ratio_);
    return false;
  }
  status_.clear();
  return factorized_ = true;
}

// Cholesky of the diagonal block (its lower triangle), then L's rows below: A21 L11⁻ᵀ.
bool SupernodalCholesky::factor_supernode(int s) {
  const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
  double* l = values_.data() + st_.l_panel[s];
  Panel D(l, w, w, Eigen::OuterStride<>(w + m));
  const Eigen::Index failed = Eigen::internal::llt_inplace<double, Eigen::Lower>::blocked(D);
  // llt_inplace stops at a pivot <= 0, not at a NaN: the diagonal says which.
  for (int k = 0; k < (failed >= 0 ? static_cast<int>(failed) + 1 : w); ++k) {
    const double d = D(k, k);
    if (failed == k || !std::isfinite(d) || !(d > 0)) {
      status_ = fmt::format(
          "supernodal Cholesky: pivot {} in column {} (supernode {}): not positive definite",
          failed == k ? "<= 0" : fmt::format("{}", d * d), f + k, s);
      return false;
    }
    smallest_pivot_ = std::min(smallest_pivot_, d * d);
    largest_pivot_ = std::max(largest_pivot_, d * d);
  }
  if (m == 0) return true;
  Panel Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
  D.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(Lb);
  return true;
}

// A22 −= L21 L21ᵀ (its lower triangle) into the L panels of the supernodes that own the rows
// below s: by columns, the diagonal and below.
void SupernodalCholesky::scatter_update(int s) {
  const int w = st_.width(s), m = st_.below(s);
  if (m == 0) return;
  double* l = values_.data() + st_.l_panel[s];
  const Panel Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
  Eigen::Map<Eigen::MatrixXd> W(update_.data(), m, m);
  W.triangularView<Eigen::Lower>() = Lb * Lb.transpose();
  const int* b = st_.rows.data() + st_.below_begin[s];
  for (int g = st_.target_begin[s]; g < st_.target_begin[s + 1]; ++g) {
    const SupernodalStructure::Target& tg = st_.targets[g];
    const int t = tg.supernode, ft = st_.first[t];
    const std::ptrdiff_t ldl = st_.width(t) + st_.below(t);
    double* L = values_.data() + st_.l_panel[t];
    const int* rel = st_.relative.data() + tg.rel - tg.begin;
    for (int j = tg.begin; j < tg.end; ++j) {
      double* Lc = L + (b[j] - ft) * ldl;
      const double* Wj = update_.data() + std::ptrdiff_t(j) * m;
      for (int i = j; i < m; ++i) Lc[rel[i]] -= Wj[i];
    }
  }
}

bool SupernodalCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_ || b.size() != st_.n) return false;
  const int n = st_.n;
  SerialEigen serial;
  for (int k = 0; k < n; ++k) y_[k] = b[st_.order[k]];
  for (int s = 0; s < st_.supernodes(); ++s) {  // L y = P b
    const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
    double* l = values_.data() + st_.l_panel[s];
    const Panel D(l, w, w, Eigen::OuterStride<>(w + m));
    Segment ys(y_.data() + f, w);
    D.triangularView<Eigen::Lower>().solveInPlace(ys);
    if (m == 0) continue;
    const Panel Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
    Segment g(gather_.data(), m);
    g.noalias() = Lb * ys;
    const int* r = st_.rows.data() + st_.below_begin[s];
    for (int i = 0; i < m; ++i) y_[r[i]] -= g[i];
  }
  for (int s = st_.supernodes() - 1; s >= 0; --s) {  // Lᵀ z = y
    const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
    double* l = values_.data() + st_.l_panel[s];
    Segment ys(y_.data() + f, w);
    if (m > 0) {
      const int* r = st_.rows.data() + st_.below_begin[s];
      Segment g(gather_.data(), m);
      for (int i = 0; i < m; ++i) g[i] = y_[r[i]];
      const Panel Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
      ys.noalias() -= Lb.transpose() * g;
    }
    const Panel D(l, w, w, Eigen::OuterStride<>(w + m));
    D.triangularView<Eigen::Lower>().transpose().solveInPlace(ys);
  }
  x.resize(n);
  for (int k = 0; k < n; ++k) x[st_.order[k]] = y_[k];
  return x.allFinite();
}

}  // namespace velum
