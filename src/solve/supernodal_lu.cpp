#include "supernodal_lu.hpp"

#include <fmt/format.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

#include "dense_kernels.hpp"
#include "ordering.hpp"
#include "supernodal_panels.hpp"

namespace velum {

using supernodal::ConstPanel;
using supernodal::Panel;
using supernodal::Segment;

bool SupernodalLu::analyze(const SparseMatrix& A) {
  factorized_ = false;
  st_ = analyse_supernodes(A, nested_dissection(A), relax_);
  values_.assign(static_cast<std::size_t>(st_.values), 0.0);
  update_.assign(static_cast<std::size_t>(st_.most_below) * st_.most_below, 0.0);
  gather_.assign(static_cast<std::size_t>(std::max(st_.most_below, 1)), 0.0);
  triangles_.assign(2 * static_cast<std::size_t>(st_.widest) * st_.widest, 0.0);
  y_.assign(static_cast<std::size_t>(st_.n), 0.0);
  swap_.assign(static_cast<std::size_t>(st_.n), 0);
  status_.clear();
  return true;
}

bool SupernodalLu::factorize(const SparseMatrix& A) {
  factorized_ = false;
  if (!st_.matches(A)) {
    status_ = "supernodal LU: the matrix does not have the analysed pattern";
    return false;
  }
  SerialEigen serial;
  std::fill(values_.begin(), values_.end(), 0.0);
  const double* a = A.valuePtr();
  for (std::size_t k = 0; k < st_.entry.size(); ++k) values_[st_.entry[k]] = a[k];
  smallest_pivot_ = std::numeric_limits<double>::infinity();
  largest_pivot_ = largest_multiplier_ = 0;
  for (int s = 0; s < st_.supernodes(); ++s) {
    if (!factor_supernode(s)) return false;
    scatter_update(s);
  }
  pivot_ratio_ = smallest_pivot_ / largest_pivot_;
  if (!(pivot_ratio_ >= kSmallestPivotRatio)) {
    status_ = fmt::format("supernodal LU: pivots span {:.1e} (nearly singular)", pivot_ratio_);
    return false;
  }
  status_.clear();
  return factorized_ = true;
}

// LU of the diagonal block with rows exchanged within it (the Uᵀ panel's columns follow),
// then L's rows below (A21 U11⁻¹) and U's columns right of it (L11⁻¹ P A12, stored transposed)
// by the register-blocked triangular solve of dense_kernels.hpp, given U11ᵀ and L11 as lower
// triangles of their own (Eigen's generic solves took 10 % of the C9 canopy's run).
bool SupernodalLu::factor_supernode(int s) {
  const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
  const std::ptrdiff_t ld = w + m;
  double* l = values_.data() + st_.l_panel[s];
  double* ub = values_.data() + st_.u_panel[s];
  for (int k = 0; k < w; ++k) {
    double* dk = l + k * ld;
    int p = k;
    double pivot = std::abs(dk[k]);
    for (int i = k + 1; i < w; ++i)
      if (std::abs(dk[i]) > pivot) {
        pivot = std::abs(dk[i]);
        p = i;
      }
    if (!(pivot > 0) || !std::isfinite(pivot)) {
      status_ = fmt::format("supernodal LU: zero pivot in column {} (supernode {})", f + k, s);
      return false;
    }
    swap_[f + k] = f + p;
    if (p != k) {
      for (int j = 0; j < w; ++j) std::swap(l[j * ld + k], l[j * ld + p]);
      if (m > 0)
        std::swap_ranges(ub + std::ptrdiff_t(k) * m, ub + std::ptrdiff_t(k + 1) * m,
                         ub + std::ptrdiff_t(p) * m);
    }
    smallest_pivot_ = std::min(smallest_pivot_, pivot);
    largest_pivot_ = std::max(largest_pivot_, pivot);
    const double inverse = 1.0 / dk[k];
    for (int i = k + 1; i < w; ++i) dk[i] *= inverse;
    for (int j = k + 1; j < w; ++j) {
      double* __restrict dj = l + j * ld;
      const double u = dj[k];
      for (int i = k + 1; i < w; ++i) dj[i] -= dk[i] * u;
    }
  }
  if (m == 0) return true;
  double* upper_t = triangles_.data();                   // U11ᵀ
  double* unit_lower = upper_t + std::ptrdiff_t(w) * w;  // L11 with its unit diagonal
  for (int j = 0; j < w; ++j) {
    for (int i = j; i < w; ++i) upper_t[j * w + i] = l[i * ld + j];
    unit_lower[j * w + j] = 1.0;
    for (int i = j + 1; i < w; ++i) unit_lower[j * w + i] = l[j * ld + i];
  }
  dense::solve_lower_transposed(l + w, ld, m, upper_t, w, w, nullptr);
  dense::solve_lower_transposed(ub, m, m, unit_lower, w, w, nullptr);
  // A NaN multiplier must fail the test below: the maximum propagates it.
  const double multiplier = ConstPanel<double>(l + w, m, w, Eigen::OuterStride<>(ld))
                                .cwiseAbs()
                                .maxCoeff<Eigen::PropagateNaN>();
  largest_multiplier_ = std::max(largest_multiplier_, multiplier);
  if (!(multiplier <= kMultiplierLimit)) {
    status_ = fmt::format(
        "supernodal LU: multiplier {:.1e} below supernode {} (a pivot outside its diagonal "
        "block is needed)",
        multiplier, s);
    return false;
  }
  return true;
}

// A22 −= L21 U12 into the panels of the supernodes that own the rows below s: the lower
// triangle (and the diagonal) by columns into L panels, the upper triangle into Uᵀ panels,
// or into the target's diagonal block when both rows are its columns.
void SupernodalLu::scatter_update(int s) {
  const int w = st_.width(s), m = st_.below(s);
  if (m == 0) return;
  const double* l = values_.data() + st_.l_panel[s];
  const Panel<double> Lb(const_cast<double*>(l) + w, m, w, Eigen::OuterStride<>(w + m));
  const Panel<double> Ub(values_.data() + st_.u_panel[s], m, w, Eigen::OuterStride<>(m));
  Eigen::Map<Eigen::MatrixXd> W(update_.data(), m, m);
  W.noalias() = Lb * Ub.transpose();
  const int* b = st_.rows.data() + st_.below_begin[s];
  for (int g = st_.target_begin[s]; g < st_.target_begin[s + 1]; ++g) {
    const SupernodalStructure::Target& tg = st_.targets[g];
    const int t = tg.supernode, wt = st_.width(t), mt = st_.below(t), ft = st_.first[t];
    const std::ptrdiff_t ldl = wt + mt;
    double* L = values_.data() + st_.l_panel[t];
    double* U = values_.data() + st_.u_panel[t];
    const int* rel = st_.relative.data() + tg.rel - tg.begin;
    for (int j = tg.begin; j < tg.end; ++j) {
      const int c = b[j] - ft;
      double* Lc = L + c * ldl;
      const double* Wj = update_.data() + std::ptrdiff_t(j) * m;
      for (int i = j; i < m; ++i) Lc[rel[i]] -= Wj[i];
      for (int i = j + 1; i < tg.end; ++i) L[c + rel[i] * ldl] -= W(j, i);
      double* Uc = U + std::ptrdiff_t(c) * mt - wt;
      for (int i = tg.end; i < m; ++i) Uc[rel[i]] -= W(j, i);
    }
  }
}

bool SupernodalLu::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!factorized_ || b.size() != st_.n) return false;
  const int n = st_.n;
  SerialEigen serial;
  for (int k = 0; k < n; ++k) y_[k] = b[st_.order[k]];
  // L y = P b, supernode by supernode: the exchanges of a supernode's rows are applied when
  // its turn comes (the multipliers of earlier supernodes were computed for the rows as they
  // were, which is the same).
  for (int s = 0; s < st_.supernodes(); ++s) {
    const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
    const double* l = values_.data() + st_.l_panel[s];
    for (int k = f; k < f + w; ++k)
      if (swap_[k] != k) std::swap(y_[k], y_[swap_[k]]);
    const Panel<double> D(const_cast<double*>(l), w, w, Eigen::OuterStride<>(w + m));
    Segment<double> ys(y_.data() + f, w);
    D.triangularView<Eigen::UnitLower>().solveInPlace(ys);
    if (m == 0) continue;
    const Panel<double> Lb(const_cast<double*>(l) + w, m, w, Eigen::OuterStride<>(w + m));
    Segment<double> g(gather_.data(), m);
    g.noalias() = Lb * ys;
    const int* r = st_.rows.data() + st_.below_begin[s];
    for (int i = 0; i < m; ++i) y_[r[i]] -= g[i];
  }
  for (int s = st_.supernodes() - 1; s >= 0; --s) {
    const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
    const double* l = values_.data() + st_.l_panel[s];
    Segment<double> ys(y_.data() + f, w);
    if (m > 0) {
      const int* r = st_.rows.data() + st_.below_begin[s];
      Segment<double> g(gather_.data(), m);
      for (int i = 0; i < m; ++i) g[i] = y_[r[i]];
      const Panel<double> Ub(values_.data() + st_.u_panel[s], m, w, Eigen::OuterStride<>(m));
      ys.noalias() -= Ub.transpose() * g;
    }
    const Panel<double> D(const_cast<double*>(l), w, w, Eigen::OuterStride<>(w + m));
    D.triangularView<Eigen::Upper>().solveInPlace(ys);
  }
  x.resize(n);
  for (int k = 0; k < n; ++k) x[st_.order[k]] = y_[k];
  return x.allFinite();
}

}  // namespace velum
