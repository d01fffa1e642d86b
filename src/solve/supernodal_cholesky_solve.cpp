// The supernodal Cholesky's solves (supernodal_cholesky.hpp): forward and back through L's
// panels in either scalar, on the tree split's threads above split_flops, and with float panels
// the iterative refinement in double that makes each solve as accurate as the double factor's.
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "supernodal_cholesky.hpp"
#include "supernodal_panels.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace velum {

using supernodal::ConstSegment;
using supernodal::Segment;
using supernodal::threads_for;

// Both passes walk each panel column by column in the order it is stored (forward up, back
// down), each column once and whole: its rows in the diagonal block and those below are
// contiguous, so the triangular solve and the product with the rows below are one loop over
// the column, against the supernode's rows gathered in `z` (its own, then those below). A pass
// is bound by reading the panels: Eigen's triangular solve then product, the back pass's
// product as dot products along the columns and the panels taken from the last to the first,
// read them in a saw-tooth the hardware prefetcher did not follow (one float pass of the
// Hencky n = 130 factor, 85 MB: 17.2 against 8.6 to 9.9 ms, docs/performance.md).

template <class T>
void SupernodalCholesky::forward(Panels<T>& p, int s, T* y, T* top_y, Work<T>& work) {
  const int f = st_.first[s], w = st_.width(s), m = st_.below(s), h = w + m;
  const T* l = p.values.data() + st_.l_panel[s];
  T* z = work.column.data();  // this supernode's solution, then minus its updates below
  std::copy(y + f, y + f + w, z);
  std::fill(z + w, z + h, T(0));
  for (int j = 0; j < w; ++j) {
    const T* column = l + std::ptrdiff_t(j) * h;
    const T x = z[j] / column[j];
    z[j] = x;
    if (const int n = h - j - 1; n > 0)
      Segment<T>(z + j + 1, n) -= x * ConstSegment<T>(column + j + 1, n);
  }
  std::copy(z, z + w, y + f);
  if (m == 0) return;
  const T* g = z + w;
  const int* r = st_.rows.data() + st_.below_begin[s];
  if (!top_y) {
    for (int i = 0; i < m; ++i) y[r[i]] += g[i];
    return;
  }
  for (int k = st_.target_begin[s]; k < st_.target_begin[s + 1]; ++k) {
    const SupernodalStructure::Target& tg = st_.targets[k];
    T* to = split_.group[tg.supernode] == TreeSplit::kTop ? top_y : y;
    for (int i = tg.begin; i < tg.end; ++i) to[r[i]] += g[i];
  }
}

template <class T>
void SupernodalCholesky::backward(Panels<T>& p, int s, T* y, Work<T>& work) {
  const int f = st_.first[s], w = st_.width(s), m = st_.below(s), h = w + m;
  const T* l = p.values.data() + st_.l_panel[s];
  T* z = work.column.data();  // this supernode's rows, then the solution at the rows below
  std::copy(y + f, y + f + w, z);
  const int* r = st_.rows.data() + st_.below_begin[s];
  for (int i = 0; i < m; ++i) z[w + i] = y[r[i]];
  // Column j's entries below its diagonal against the solution there, read downwards.
  for (int j = w - 1; j >= 0; --j) {
    const T* column = l + std::ptrdiff_t(j) * h;
    const int n = h - j - 1;
    const T below =
        n > 0 ? ConstSegment<T>(column + j + 1, n).reverse().dot(Segment<T>(z + j + 1, n).reverse())
              : T(0);
    z[j] = (z[j] - below) / column[j];
  }
  std::copy(z, z + w, y + f);
}

bool SupernodalCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  return solve_within(b, x, 0.0);
}

bool SupernodalCholesky::solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                      double residual) {
  if (!factorized_ || b.size() != st_.n) return false;
  SerialEigen serial;
  if (float_factor_) return solve_refined(b, x, residual);
  solve_with(double_, b, x);
  return x.allFinite();
}

template <class T>
void SupernodalCholesky::solve_with(Panels<T>& p, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const int n = st_.n;
  T* y = p.y.data();
  // A float solve of b / ‖b‖∞: neither overflows nor underflows in the panels' range.
  double scale = 1;
  if constexpr (!std::is_same_v<T, double>) {
    scale = b.lpNorm<Eigen::Infinity>();
    if (!(scale > 0) || !std::isfinite(scale)) scale = 1;
  }
  for (int k = 0; k < n; ++k) y[k] = static_cast<T>(b[st_.order[k]] / scale);
  if (splits_) {
    solve_split(p);
  } else {
    for (int s = 0; s < st_.supernodes(); ++s)
      forward(p, s, y, static_cast<T*>(nullptr), p.work[0]);
    for (int s = st_.supernodes() - 1; s >= 0; --s) backward(p, s, y, p.work[0]);
  }
  x.resize(n);
  for (int k = 0; k < n; ++k) x[st_.order[k]] = static_cast<double>(y[k]) * scale;
}

double SupernodalCholesky::backward_error(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                                          Eigen::VectorXd& r) {
  // r = b − A x from A's lower triangle: column j gives r_j its dot product with x (the
  // diagonal and, by symmetry, A's row j right of it) and spreads x_j down its rows. With a
  // split, the columns are cut in two halves, one per thread, the second half's sums kept in
  // a vector of its own and added after: the same sums in the same order on one thread or
  // two, so that both give the same bits.
  const int n = st_.n;
  r = b;
  const int* start = lower_.outerIndexPtr();
  const int* row = lower_.innerIndexPtr();
  const double* value = lower_.valuePtr();
  const int halves = splits_ ? 2 : 1;
  second_half_.setZero(halves == 2 ? n : 0);
  auto columns = [&](int begin, int end, double* sums) {
    for (int j = begin; j < end; ++j) {
      const double xj = x[j];
      double dot = 0;
      int k = start[j];
      if (k < start[j + 1] && row[k] == j) dot = value[k++] * xj;
      for (; k < start[j + 1]; ++k) {
        const int i = row[k];
        dot += value[k] * x[i];
        sums[i] -= value[k] * xj;
      }
      sums[j] -= dot;
    }
  };
  if (halves == 1) {
    columns(0, n, r.data());
  } else {
#pragma omp parallel for schedule(static) num_threads(std::min(2, omp_get_max_threads()))
    for (int h = 0; h < 2; ++h)
      columns(h * (n / 2), h == 0 ? n / 2 : n, h == 0 ? r.data() : second_half_.data());
    r += second_half_;
  }
  const double rn = r.lpNorm<Eigen::Infinity>();
  if (!r.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  return rn == 0 ? 0 : rn / (a_norm_ * x.lpNorm<Eigen::Infinity>());
}

// The float factor's solution corrected in double (the iterative refinement of Wilkinson,
// Moler): x ← x + L⁻ᵀ L⁻¹ (b − A x) with L in float and the residual in double, which converges
// to the double solution's accuracy when cond(A) times float's rounding is well below one. It
// stops early where ‖r‖₂ <= enough (the caller needs no more).
bool SupernodalCholesky::solve_refined(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                       double enough) {
  solve_with(float_, b, x);
  ++counts_.float_solves;
  // The first step alone, unchecked, when asked; one that is not finite goes on as a checked
  // solve (refined or, failing that, by the double factor).
  if (std::isinf(enough) && x.allFinite()) return true;
  double error = backward_error(b, x, r_);
  if (const double bn = b.norm(); bn > 0) float_pass_accuracy_ = r_.norm() / bn;
  // LAPACK's DSPOSV: refined when ‖r‖∞ <= √n ε ‖A‖∞ ‖x‖∞ (ε = 2⁻⁵³).
  const double target = std::sqrt(double(st_.n)) * kRoundoff;
  auto done = [&] { return error <= target || (enough > 0 && r_.norm() <= enough); };
  bool refined = false;
  int corrections = 0;
  for (; corrections < kMostRefinements && !done(); ++corrections) {
    solve_with(float_, r_, dx_);
    ++counts_.float_solves;
    refined = true;
    x += dx_;
    const double before = error;
    error = backward_error(b, x, r_);
    if (!(error <= 0.5 * before)) break;  // stalled, or not finite
  }
  if (refined) ++counts_.refined_solves;
  counts_.last_backward_error = error;
  if (done()) {
    if (corrections > kSlowRefinements)
      pause_float();  // more work than the float factor saved
    else
      pause_length_ = 0;
    return x.allFinite();
  }
  pause_float();
  // Not refined to the double factor's accuracy: the double factor, kept for this matrix.
  ++counts_.double_fallbacks;
  float_factor_ = false;
  release(float_);
  allocate(double_);
  SerialOpenBlas serial_blas(OpenBlasKernels::loaded());
  if (!factorize_in(double_)) {
    factorized_ = false;
    return false;
  }
  solve_with(double_, b, x);
  counts_.last_backward_error = backward_error(b, x, r_);
  return x.allFinite();
}

// The next 1, 2, 4 ... 64 factorisations in double.
void SupernodalCholesky::pause_float() {
  float_pass_accuracy_ = std::numeric_limits<double>::quiet_NaN();  // measured again on return
  pause_length_ = std::clamp(2 * pause_length_, 1, 64);
  double_pause_ = pause_length_;
}

// Forward: the groups at once, group 1's updates of the top's rows in top_y (added after);
// the top on one thread, forward and back; the groups back at once (they read the top's rows
// and write their own).
template <class T>
void SupernodalCholesky::solve_split(Panels<T>& p) {
  const int threads = threads_for(p.work.size());
  T* y = p.y.data();
  T* top_y = p.top_y.data();
  const int ntop = static_cast<int>(split_.top.size());
#pragma omp parallel num_threads(threads)
  {
    const int me = omp_get_thread_num(), team = omp_get_num_threads();
    Work<T>& work = p.work[me];
    work.make(st_.most_below, st_.widest);  // a thread that sat out the factorisation
#pragma omp for schedule(static)
    for (int k = 0; k < ntop; ++k)
      for (int j = st_.first[split_.top[k]]; j < st_.first[split_.top[k] + 1]; ++j) top_y[j] = 0;
    for (int g = me; g < 2; g += team)
      for (const int s : split_.members[g]) forward(p, s, y, g == 1 ? top_y : nullptr, work);
#pragma omp barrier
#pragma omp single
    {
      for (const int t : split_.top)
        for (int j = st_.first[t]; j < st_.first[t + 1]; ++j) y[j] += top_y[j];
      for (const int t : split_.top) forward(p, t, y, static_cast<T*>(nullptr), work);
      for (int k = ntop - 1; k >= 0; --k) backward(p, split_.top[k], y, work);
    }
    for (int g = me; g < 2; g += team)
      for (auto s = split_.members[g].rbegin(); s != split_.members[g].rend(); ++s)
        backward(p, *s, y, work);
  }
}

}  // namespace velum
