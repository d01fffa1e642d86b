#include "supernodal_cholesky.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "dense_kernels.hpp"
#include "dense_packets.hpp"
#include "ordering.hpp"
#include "supernodal_panels.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace velum {

using supernodal::ConstPanel;
using supernodal::Matrix;
using supernodal::Panel;
using supernodal::Segment;
using supernodal::threads_for;

namespace {

// The top's dense work is cut into blocks of these many rows (the triangular solve) and
// columns (the update), whichever thread takes them.
constexpr int kRowBlock = 96;
constexpr int kColumnBlock = 48;
// Clearing and loading the panels: chunks of this many values.
constexpr std::ptrdiff_t kClearChunk = 1 << 16;

// d[i] −= u[i] and u[i] = 0 for i < n. The runs are short (whole nodes of 3 equations: 3, 6,
// 9 ... rows): the last partial packet goes as one masked vector on AVX-512 (a scalar tail
// there cost 13 % of the subtraction's samples).
template <class T>
inline void subtract_run(T* __restrict d, T* __restrict u, int n) {
  using dense::packets::kLanes;
  using dense::packets::load;
  using dense::packets::store;
  using Eigen::internal::psub;
  const auto zero = Eigen::internal::pset1<dense::packets::Packet<T>>(T(0));
  int i = 0;
  for (; i + kLanes<T> <= n; i += kLanes<T>) {
    store(d + i, psub(load(d + i), load(u + i)));
    store(u + i, zero);
  }
  if (i < n) {
    using dense::packets::load_first;
    using dense::packets::store_first;
    store_first(d + i, psub(load_first(d + i, n - i), load_first(u + i, n - i)), n - i);
    store_first(u + i, zero, n - i);
  }
}

// Lc[rel[i]] −= W[i] for i in [j, m), by runs of rows that land contiguously in Lc: the rows
// [run[k], run[k + 1]) for k < count, run[0] <= j < run[1] and run[count] = m. W[i] is left
// zero: the work space stays zero between updates, which add their products to it (Eigen's
// products into a destination clear it first, a pass over it of their own; here it is cleared
// by the pass that reads it, while it is in cache).
template <class T>
inline void subtract_runs(T* __restrict Lc, T* __restrict W, const int* rel, const int* run,
                          int count, int j) {
  for (int k = 0; k < count; ++k) {
    const int begin = std::max(run[k], j);
    subtract_run(Lc + rel[begin], W + begin, run[k + 1] - begin);
  }
}

// The runs of the rows [begin, m) that land contiguously in a target (rel ascends); returns
// their count.
inline int find_runs(const int* rel, int begin, int m, int* run) {
  int count = 0;
  run[count++] = begin;
  for (int i = begin + 1; i < m; ++i)
    if (rel[i] != rel[i - 1] + 1) run[count++] = i;
  run[count] = m;
  return count;
}

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

bool SupernodalCholesky::analyze(const SparseMatrix& A) {
  factorized_ = false;
  float_factor_ = false;
  blas_ = OpenBlasKernels::found();
  st_ = analyse_supernodes(A, nested_dissection(A), relax_, Factor::kCholesky);
  splits_ = st_.flops >= split_flops_;
  split_ = splits_ ? split_tree(st_) : TreeSplit{};
  if (!plan_panels()) {
    status_ =
        "supernodal Cholesky: a supernode's panel holds more than 2^31 values, or A's pattern "
        "is not symmetric";
    return false;
  }
  release(double_);
  release(float_);
  // Mixed: the float panels now, the double ones at the first fallback.
  mixed_ = precision_ == Precision::kMixed ||
           (precision_ == Precision::kAuto && st_.flops >= kMixedFlops);
  counts_ = MixedCounts{};
  float_pass_accuracy_ = std::numeric_limits<double>::quiet_NaN();
  double_pause_ = pause_length_ = 0;
  if (mixed_)
    allocate(float_);
  else
    allocate(double_);
  make_lower(A);
  status_.clear();
  return true;
}

// lower_'s pattern: A's rows at or below the diagonal, where the loads read them (its values
// are copied at each factorisation).
void SupernodalCholesky::make_lower(const SparseMatrix& A) {
  const int n = st_.n;
  std::vector<int>& begin = st_.lower_begin;
  lower_.resize(n, n);
  lower_.resizeNonZeros(begin[n]);
  std::copy(begin.begin(), begin.end(), lower_.outerIndexPtr());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  int* rows = lower_.innerIndexPtr();
  for (int j = 0; j < n; ++j) {
    const int m = begin[j + 1] - begin[j];
    std::copy(inner + outer[j + 1] - m, inner + outer[j + 1], rows + begin[j]);
  }
  begin = {};
}

template <class T>
void SupernodalCholesky::release(Panels<T>& p) {
  p.values.assign(0);
  p.top_copy.assign(0);
  p.y = {};
  p.top_y = {};
  p.work = {};
  p.allocated = false;
}

template <class T>
void SupernodalCholesky::allocate(Panels<T>& p) {
  if (p.allocated) return;
  // Two threads' work spaces at least, whatever the count now (it may grow before factorize).
  // Sized before first_touch, which shares the panels out by it. Each work space is made by
  // the thread that uses it, at its first factorisation (Work::make): its first touches then
  // run on that thread, not all on this one.
  p.work.assign(splits_ ? std::max(2, omp_get_max_threads()) : 1, Work<T>{});
  p.values.assign(static_cast<std::size_t>(st_.values));
  if (splits_) first_touch(p);
  // Not cleared here: factorize_split clears it before each use.
  p.top_copy.assign(static_cast<std::size_t>(split_.top_values));
  p.y.assign(static_cast<std::size_t>(st_.n), T(0));
  p.top_y.assign(splits_ ? static_cast<std::size_t>(st_.n) : 0, T(0));
  p.allocated = true;
}

bool SupernodalCholesky::factorize(const SparseMatrix& A) {
  factorized_ = false;
  float_factor_ = false;
  if (!st_.matches(A)) {
    status_ = "supernodal Cholesky: the matrix does not have the analysed pattern";
    return false;
  }
  SerialEigen serial;
  SerialOpenBlas serial_blas(OpenBlasKernels::loaded());
  // A's lower triangle copied (kept as factorised: the loads read it, and the refinement's
  // residuals and a fallback to double), with ‖A‖∞ summed in the same pass over A's columns
  // (A is symmetric: its rows' sums are its columns'). On the threads a split factorisation
  // runs on (a maximum is exact in any order): on one, this serial pass held the second
  // thread idle for a visible share of a two-thread run.
  {
    const int* outer = A.outerIndexPtr();
    const int* stored = A.innerNonZeroPtr();  // an uncompressed A's counts
    const double* from = A.valuePtr();
    double* to = lower_.valuePtr();
    const int* begin = lower_.outerIndexPtr();
    const int columns = st_.n;
    const int threads = splits_ ? omp_get_max_threads() : 1;
    double norm = 0;
#pragma omp parallel for schedule(static) reduction(max : norm) num_threads(threads)
    for (int j = 0; j < columns; ++j) {
      const int end = stored ? outer[j] + stored[j] : outer[j + 1];
      double sum = 0;
      for (int k = outer[j]; k < end; ++k) sum += std::abs(from[k]);
      const int m = begin[j + 1] - begin[j];
      std::copy(from + end - m, from + end, to + begin[j]);
      norm = std::max(norm, sum);
    }
    a_norm_ = norm;
  }
  if (mixed_) {
    if (double_pause_ > 0) {
      --double_pause_;
    } else {
      // One precision's panels in memory at a time (a switch costs their first touches).
      release(double_);
      allocate(float_);
      if (factorize_in(float_)) {
        ++counts_.float_factorizations;
        return factorized_ = float_factor_ = true;
      }
      ++counts_.float_refusals;
      pause_float();
    }
    release(float_);
  }
  allocate(double_);
  return factorized_ = factorize_in(double_);
}

template <class T>
bool SupernodalCholesky::factorize_in(Panels<T>& p) {
  for (Work<T>& w : p.work) {
    w.smallest = std::numeric_limits<double>::infinity();
    w.largest = 0;
    w.failed = false;
    w.status.clear();
  }
  if (splits_) {
    factorize_split(p, lower_.valuePtr());
  } else {
    Work<T>& w = p.work[0];
    w.make(st_.most_below, st_.widest);
    for (int s = 0; s < st_.supernodes() && !w.failed; ++s) {
      start_panels(p, s, lower_.valuePtr());
      if (!factor_diagonal(p, s, w)) break;
      solve_below(p, s, 0, st_.below(s));
      scatter_update(p, s, w, static_cast<T*>(nullptr));
    }
  }
  double smallest = std::numeric_limits<double>::infinity(), largest = 0;
  for (const Work<T>& w : p.work) {
    if (w.failed) {
      status_ = w.status;
      return false;
    }
    smallest = std::min(smallest, w.smallest);
    largest = std::max(largest, w.largest);
  }
  pivot_ratio_ = smallest / largest;
  if (!(pivot_ratio_ >= kSmallestPivotRatio)) {
    status_ =
        fmt::format("supernodal Cholesky: pivots span {:.1e} (nearly singular)", pivot_ratio_);
    return false;
  }
  status_.clear();
  return true;
}

// Each group's panels cleared first by the thread that factorises them, the top's by blocks:
// touched by one thread for all, the two threads' factorisations ran slower (the host seems
// to keep a page near the virtual CPU that touched it first).
template <class T>
void SupernodalCholesky::first_touch(Panels<T>& p) {
  const int threads = threads_for(p.work.size());
  auto clear = [&](int s) {
    std::fill_n(p.values.data() + st_.l_panel[s],
                std::ptrdiff_t(st_.width(s) + st_.below(s)) * st_.width(s), T(0));
  };
  const int ntop = static_cast<int>(split_.top.size());
#pragma omp parallel num_threads(threads)
  {
    const int me = omp_get_thread_num(), team = omp_get_num_threads();
    for (int g = me; g < 2; g += team)
      for (const int s : split_.members[g]) clear(s);
#pragma omp for schedule(static)
    for (int k = 0; k < ntop; ++k) clear(split_.top[k]);
  }
}

// Where each panel is cleared and given A's entries (A's lower triangle): just before the
// first supernode whose update reaches it is eliminated (or before itself, for a supernode that
// no update reaches), so that it is in cache when the updates arrive, rather than all panels in
// one pass first (a pass over all of them through memory, 164 MB for 150k equations). With a
// split, the top's panels (reached from both groups) are started before the groups start.
bool SupernodalCholesky::plan_panels() {
  const int ns = st_.supernodes();
  std::vector<int> start_at(static_cast<std::size_t>(ns));
  for (int t = 0; t < ns; ++t) start_at[t] = t;
  for (int d = ns - 1; d >= 0; --d)  // the smallest source last
    for (int g = st_.target_begin[d]; g < st_.target_begin[d + 1]; ++g)
      start_at[st_.targets[g].supernode] = d;
  start_begin_.assign(static_cast<std::size_t>(ns) + 1, 0);
  for (int t = 0; t < ns; ++t)
    if (!splits_ || split_.group[t] != TreeSplit::kTop) ++start_begin_[start_at[t] + 1];
  for (int s = 0; s < ns; ++s) start_begin_[s + 1] += start_begin_[s];
  starts_.resize(static_cast<std::size_t>(start_begin_[ns]));
  std::vector<int> next(start_begin_.begin(), start_begin_.end() - 1);
  for (int t = 0; t < ns; ++t)
    if (!splits_ || split_.group[t] != TreeSplit::kTop) starts_[next[start_at[t]]++] = t;
  // A's entries by the panel they go to, each with its place in it (analyse_supernodes made
  // the lists: empty when a panel's places do not fit in an int).
  if (st_.load_begin.empty()) return false;
  load_begin_ = std::move(st_.load_begin);
  loads_ = std::move(st_.loads);
  return true;
}

// Supernode t's panel cleared and given A's entries (rounded to T).
template <class T>
void SupernodalCholesky::start_panel(Panels<T>& p, int t, const double* a) {
  T* L = p.values.data() + st_.l_panel[t];
  std::fill_n(L, std::ptrdiff_t(st_.width(t) + st_.below(t)) * st_.width(t), T(0));
  for (int k = load_begin_[t]; k < load_begin_[t + 1]; ++k)
    L[loads_[k].at] = static_cast<T>(a[loads_[k].a]);
}

template <class T>
void SupernodalCholesky::start_panels(Panels<T>& p, int s, const double* a) {
  for (int k = start_begin_[s]; k < start_begin_[s + 1]; ++k) start_panel(p, starts_[k], a);
}

// Cholesky of the diagonal block (its lower triangle).
template <class T>
bool SupernodalCholesky::factor_diagonal(Panels<T>& p, int s, Work<T>& work) {
  const int f = st_.first[s], w = st_.width(s), m = st_.below(s);
  T* l = p.values.data() + st_.l_panel[s];
  const ConstPanel<T> D(l, w, w, Eigen::OuterStride<>(w + m));
  const std::ptrdiff_t failed = dense::cholesky_lower(l, w + m, w, blas_);
  // cholesky_lower stops at a pivot <= 0, not at a NaN: the diagonal says which.
  for (int k = 0; k < (failed >= 0 ? static_cast<int>(failed) + 1 : w); ++k) {
    const double d = D(k, k);
    if (failed == k || !std::isfinite(d) || !(d > 0)) {
      work.status = fmt::format(
          "supernodal Cholesky: pivot {} in column {} (supernode {}): not positive definite",
          failed == k ? "<= 0" : fmt::format("{}", d * d), f + k, s);
      work.failed = true;
      return false;
    }
    work.smallest = std::min(work.smallest, d * d);
    work.largest = std::max(work.largest, d * d);
  }
  return true;
}

// L's rows [begin, end) below the diagonal block: A21 L11⁻ᵀ (by dense_kernels.cpp's kernel,
// faster than Eigen's trsm at every panel width, most of all on narrow panels).
template <class T>
void SupernodalCholesky::solve_below(Panels<T>& p, int s, int begin, int end) {
  if (end <= begin) return;
  const int w = st_.width(s), m = st_.below(s);
  T* l = p.values.data() + st_.l_panel[s];
  dense::solve_lower_transposed(l + w + begin, w + m, end - begin, l, w + m, w, blas_);
}

// A22 −= L21 L21ᵀ (its lower triangle) into the L panels of the supernodes that own the rows
// below s: by columns, the diagonal and below (subtract_update).
template <class T>
void SupernodalCholesky::scatter_update(Panels<T>& p, int s, Work<T>& work, T* top_copy) {
  const int w = st_.width(s), m = st_.below(s);
  if (m == 0) return;
  T* l = p.values.data() + st_.l_panel[s];
  if (blas_ && w >= kBlasWidth) {
    blas_->syrk_lower<T>(m, w, T(1), l + w, w + m, work.update.data(), m);  // work.update is zero
  } else if (w >= kBlasWidth && m >= kPackedRows) {
    dense::syrk_lower<T>(m, w, T(1), l + w, w + m, work.update.data(), m);
  } else if (w <= dense::kNarrowDepth) {
    dense::syrk_lower_narrow<T>(m, w, l + w, w + m, work.update.data(), m);
  } else {
    const Panel<T> Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
    Eigen::Map<Matrix<T>> W(work.update.data(), m, m);  // zero (subtract_runs)
    W.template triangularView<Eigen::Lower>() += Lb * Lb.transpose();
  }
  subtract_update(p, s, 0, m, m, work, top_copy);
}

// The update's columns [begin, end), the rows from begin down (the lower triangle of its top
// square, the rectangle below), into the panels they reach. Different columns reach different
// panel columns: threads may take different column blocks of one supernode.
template <class T>
void SupernodalCholesky::update_columns(Panels<T>& p, int s, int begin, int end, Work<T>& work) {
  const int w = st_.width(s), m = st_.below(s), rows = m - begin, cols = end - begin;
  const T* l = p.values.data() + st_.l_panel[s];
  // The update's columns: rows x cols at work.update, zero (subtract_runs): the products add.
  T* W0 = work.update.data();
  if (blas_ && w >= kBlasWidth) {
    const int ld = w + m;
    blas_->syrk_lower<T>(cols, w, T(1), l + w + begin, ld, W0, rows);
    if (rows > cols)
      blas_->gemm_abt<T>(rows - cols, cols, w, T(1), l + w + end, ld, l + w + begin, ld, W0 + cols,
                         rows);
  } else if (w >= kBlasWidth && rows >= kPackedRows) {
    const int ld = w + m;
    dense::syrk_lower<T>(cols, w, T(1), l + w + begin, ld, W0, rows);
    if (rows > cols)
      dense::gemm_abt<T>(rows - cols, cols, w, T(1), l + w + end, ld, l + w + begin, ld, W0 + cols,
                         rows);
  } else if (w <= dense::kNarrowDepth) {
    const int ld = w + m;
    dense::syrk_lower_narrow<T>(cols, w, l + w + begin, ld, W0, rows);
    if (rows > cols)
      dense::gemm_abt_narrow<T>(rows - cols, cols, w, l + w + end, ld, l + w + begin, ld, W0 + cols,
                                rows);
  } else {
    const ConstPanel<T> Lb(l + w, m, w, Eigen::OuterStride<>(w + m));
    const auto B = Lb.middleRows(begin, cols);
    Eigen::Map<Matrix<T>> W(W0, rows, cols);
    W.topRows(cols).template triangularView<Eigen::Lower>() += B * B.transpose();
    if (rows > cols)
      W.bottomRows(rows - cols).noalias() += Lb.bottomRows(rows - cols) * B.transpose();
  }
  subtract_update(p, s, begin, end, rows, work, static_cast<T*>(nullptr));
}

// The update's columns [begin, end), held in work.update from row `begin` down (column j at
// (j − begin) ldw, row i at i − begin), subtracted from the panels they reach. With
// `top_copy`, what goes to the top's panels goes to their copy there instead.
template <class T>
void SupernodalCholesky::subtract_update(Panels<T>& p, int s, int begin, int end,
                                         std::ptrdiff_t ldw, Work<T>& work, T* top_copy) {
  const int m = st_.below(s);
  const int* b = st_.rows.data() + st_.below_begin[s];
  for (int g = st_.target_begin[s]; g < st_.target_begin[s + 1]; ++g) {
    const SupernodalStructure::Target& tg = st_.targets[g];
    if (tg.end <= begin || tg.begin >= end) continue;
    const int t = tg.supernode, ft = st_.first[t];
    const std::ptrdiff_t ldl = st_.width(t) + st_.below(t);
    T* L = top_copy && split_.top_offset[t] >= 0 ? top_copy + split_.top_offset[t]
                                                 : p.values.data() + st_.l_panel[t];
    const int* rel = st_.relative.data() + tg.rel - tg.begin;
    const int first = std::max(tg.begin, begin);
    int* run = work.runs.data();
    const int count = find_runs(rel, first, m, run);
    for (int j = first, r = 0; j < std::min(tg.end, end); ++j) {
      while (run[r + 1] <= j) ++r;
      T* Lc = L + (b[j] - ft) * ldl;
      T* Wj = work.update.data() + (j - begin) * ldw - begin;
      subtract_runs(Lc, Wj, rel, run + r, count - r, j);
    }
  }
}

// Both groups at once (one thread each; one thread takes both in turn), each writing its
// updates of the top into its own place (group 0 the panels, group 1 their copy); the copy
// added; then the top's supernodes in order, each one's row and column blocks shared.
template <class T>
void SupernodalCholesky::factorize_split(Panels<T>& p, const double* a) {
  const int threads = threads_for(p.work.size());
  T* copy = p.top_copy.data();
  const std::ptrdiff_t nc = split_.top_values;
  const int ntop = static_cast<int>(split_.top.size());
  bool failed = false;
#pragma omp parallel num_threads(threads)
  {
    const int me = omp_get_thread_num(), team = omp_get_num_threads();
    Work<T>& work = p.work[me];
    work.make(st_.most_below, st_.widest);
#pragma omp for schedule(static)
    for (std::ptrdiff_t c = 0; c < nc; c += kClearChunk)
      std::fill(copy + c, copy + std::min(nc, c + kClearChunk), T(0));
#pragma omp for schedule(dynamic)
    for (int k = 0; k < ntop; ++k) start_panel(p, split_.top[k], a);
    for (int g = me; g < 2 && !work.failed; g += team) {
      const double start = thread_seconds();
      for (const int s : split_.members[g]) {
        start_panels(p, s, a);
        if (!factor_diagonal(p, s, work)) break;
        solve_below(p, s, 0, st_.below(s));
        scatter_update(p, s, work, g == 1 ? copy : nullptr);
      }
      split_seconds_.group[g] = thread_seconds() - start;
    }
#pragma omp barrier
    const double top_start = thread_seconds();
#pragma omp single
    for (const Work<T>& w : p.work) failed = failed || w.failed;
    if (!failed) {
#pragma omp for schedule(dynamic)
      for (int k = 0; k < ntop; ++k) {
        const int t = split_.top[k];
        const std::ptrdiff_t size = std::ptrdiff_t(st_.width(t) + st_.below(t)) * st_.width(t);
        T* L = p.values.data() + st_.l_panel[t];
        const T* C = copy + split_.top_offset[t];
        for (std::ptrdiff_t i = 0; i < size; ++i) L[i] += C[i];
      }
      for (const int s : split_.top) {
#pragma omp single
        failed = !factor_diagonal(p, s, work);
        if (failed) break;
        const int m = st_.below(s);
#pragma omp for schedule(static)
        for (int r = 0; r < m; r += kRowBlock) solve_below(p, s, r, std::min(m, r + kRowBlock));
#pragma omp for schedule(dynamic)
        for (int c = 0; c < m; c += kColumnBlock)
          update_columns(p, s, c, std::min(m, c + kColumnBlock), work);
      }
    }
    if (me == 0) split_seconds_.top = thread_seconds() - top_start;
  }
}

// The solves (supernodal_cholesky_solve.cpp) use these with either panel scalar.
template bool SupernodalCholesky::factorize_in(Panels<double>&);
template void SupernodalCholesky::allocate(Panels<double>&);
template void SupernodalCholesky::release(Panels<float>&);

}  // namespace velum
