// A supernodal Cholesky factorisation (LLᵀ) for symmetric positive definite matrices (the
// statics of a prestressed membrane, Hencky's problem): the symbolic analysis of the supernodal
// LU (supernodes.hpp) with L's panels only, dense kernels (Eigen; OpenBLAS's syrk and gemm for the
// wider updates where its AVX-512 kernels run: blas_kernels.hpp) for the diagonal block's
// Cholesky, the triangular solve of the rows below and the symmetric update, no pivoting. Each
// update is scattered into the panels it reaches by runs of rows contiguous there; each panel
// is cleared and given A's entries just before the first update reaches it. A
// pivot that is not positive and finite, or pivots (l_kk²) spanning more than
// 1/kSmallestPivotRatio, and the factorisation reports failure: the caller factorises with
// MUMPS's LDLᵀ, which also gives the inertia (`auto`).
//
// Above `split_flops` the factorisation and the solves follow a split of the elimination tree
// (tree_split.hpp): two groups of independent subtrees on two OpenMP threads, then the top
// separators with each supernode's dense work shared. The split and the blocks the work is cut
// into depend on the matrix's structure alone: one thread or two give the same result to the
// bit (not the same as below `split_flops`, to round-off).
//
// Precision::kMixed (and kAuto above kMixedFlops, `auto`'s choice): the same factorisation with
// float panels (Eigen's float kernels: more values per vector, half the bytes), each solve
// refined in double against A as factorised, and the double factorisation where the float one
// is refused or its refinement falls short, so that every solve is as accurate as the double
// factor's. The same structure and split: one thread or two still give the same bits.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "huge_pages.hpp"
#include "supernodes.hpp"
#include "tree_split.hpp"
#include "velum/solve/blas_kernels.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {

class SupernodalCholesky final : public LinearSolver {
 public:
  static constexpr double kSmallestPivotRatio = 1e-12;
  /// Factorisations below this many flops run as one sequence of supernodes on the calling
  /// thread (a tree split costs more than it gives there).
  static constexpr double kSplitFlops = 5e7;
  /// Updates of supernodes this wide or wider go to OpenBLAS's syrk and gemm where its
  /// AVX-512 kernels run (blas_kernels.hpp), else to dense_products.cpp's packed products.
  static constexpr int kBlasWidth = 64;
  /// ... and dense_products.cpp's for this many rows below or more; below this many rows the
  /// packing does not pay for itself, and updates of supernodes up to dense::kNarrowDepth
  /// wide go to its narrow products (no packing: as fast as Eigen's at 3 to 24 columns, 1.15x
  /// to 1.3x from 48 to 250; bench BM_UpdateProduct), wider ones to Eigen's.
  static constexpr int kPackedRows = 256;
  /// The panels' scalar: double, or float with iterative refinement in double (kMixed): each
  /// solve corrects x by the float factor's solution of the residual r = b − A x, computed in
  /// double with A as factorised, until ‖r‖∞ <= √n ε ‖A‖∞ ‖x‖∞ (ε = kRoundoff, double's unit
  /// roundoff: LAPACK's DSPOSV's test), in at most kMostRefinements corrections while each one
  /// at least halves ‖r‖∞ / (‖A‖∞ ‖x‖∞); otherwise the matrix is factorised in double and
  /// solved with that (as is a matrix whose float factorisation fails). After such a fallback,
  /// or a solve that took more than kSlowRefinements corrections (each costs about 0.6 of a
  /// double solve; the float factorisation saves about 2.5 double solves at 150k equations:
  /// beyond 6 a factor costs more than it saves), the next 1, 2, 4 ... 64 factorisations are
  /// in double (a float factor that serves resets the count). One precision's panels are in
  /// memory at a time. kAuto: kMixed for factorisations of at least kMixedFlops, kDouble below
  /// (where the refinement's extra solves cost more than the float factor saves).
  enum class Precision { kDouble, kMixed, kAuto };
  static constexpr int kMostRefinements = 10;
  static constexpr int kSlowRefinements = 6;
  static constexpr double kRoundoff = 0x1p-53;
  static constexpr double kMixedFlops = 4e8;

  explicit SupernodalCholesky(const Amalgamation& relax = {}, double split_flops = kSplitFlops,
                              Precision precision = Precision::kDouble)
      : relax_(relax), split_flops_(split_flops), precision_(precision) {}
  std::string_view name() const override { return "supernodal-cholesky"; }
  bool symmetric_only() const override { return true; }
  bool analyze(const SparseMatrix& A) override;
  /// Reads A's lower triangle only (A stored whole: its pattern symmetric) and keeps a copy of
  /// it, the matrix as factorised (the mixed refinement's residuals, a fallback to double).
  bool factorize(const SparseMatrix& A) override;
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  /// With float panels, the refinement stops as soon as ‖b − A x‖₂ <= `residual` (or at the
  /// DSPOSV test, whichever comes first); with double panels, as solve.
  bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) override;
  /// With the float factor, its solve's relative residual as measured at the last solve that
  /// was checked (NaN until then, and after a fall-back to double); 0 with the double factor.
  double one_pass_accuracy() const override { return float_factor_ ? float_pass_accuracy_ : 0.0; }
  std::string status() const override { return status_; }
  /// Definite: no negative pivot after a factorisation that succeeded.
  int negative_pivots() const override { return factorized_ ? 0 : -1; }

  const SupernodalStructure& structure() const { return st_; }
  /// The tree split the factorisation follows (empty groups below `split_flops`).
  const TreeSplit& split() const { return split_; }
  bool splits() const { return splits_; }
  /// CPU seconds of the last split factorisation's parts (each group on its thread, the top
  /// on the calling thread), to check the split's balance.
  struct SplitSeconds {
    double group[2] = {0, 0}, top = 0;
  };
  const SplitSeconds& split_seconds() const { return split_seconds_; }
  /// min l_kk² / max l_kk² of the last factorisation.
  double pivot_ratio() const { return pivot_ratio_; }
  /// Mixed precision: whether the last factorisation is the float one (else double); since the
  /// analysis, the float factorisations that succeeded and those refused (a pivot not positive
  /// in float: the double factorisation followed), the float solves (the first of each solve
  /// and its corrections), the solves that were refined, and those whose refinement fell short
  /// (the double factorisation and solve followed).
  bool float_factor() const { return float_factor_; }
  struct MixedCounts {
    long float_factorizations = 0, float_refusals = 0;
    long float_solves = 0, refined_solves = 0, double_fallbacks = 0;
    double last_backward_error = 0;  ///< ‖r‖∞ / (‖A‖∞ ‖x‖∞) of the last mixed solve
  };
  const MixedCounts& mixed_counts() const { return counts_; }
  /// Whether factorisations of the analysed pattern try float first (kMixed, or kAuto above
  /// kMixedFlops).
  bool mixed() const { return mixed_; }

 private:
  template <class T>
  struct Work {  ///< one thread's
    std::vector<T> update;
    std::vector<T> column;  ///< the solves' one supernode's rows (its own, then those below)
    std::vector<int> runs;  ///< a scatter's runs of contiguous rows
    double smallest = 0, largest = 0;
    bool failed = false;
    std::string status;
    /// Sized for updates of up to `most_below` rows and supernodes of up to `widest` columns
    /// (first call after an analysis only).
    void make(int most_below, int widest) {
      const std::size_t mb = static_cast<std::size_t>(std::max(most_below, 1));
      if (runs.size() == mb + 1 && column.size() == mb + static_cast<std::size_t>(widest)) return;
      update.assign(mb * mb, T(0));
      column.assign(mb + static_cast<std::size_t>(widest), T(0));
      runs.assign(mb + 1, 0);
    }
  };
  /// L's panels in one precision, with the work spaces of the factorisation and solves.
  template <class T>
  struct Panels {
    HugePageBuffer<T> values, top_copy;  ///< the L panels; the top's panels' copy (tree_split.hpp)
    std::vector<T> y, top_y;
    std::vector<Work<T>> work;
    bool allocated = false;  ///< for the current analysis
  };

  using Load = SupernodalStructure::Load;
  bool plan_panels();
  template <class T>
  void allocate(Panels<T>& p);  ///< unless allocated
  template <class T>
  void release(Panels<T>& p);
  template <class T>
  void first_touch(Panels<T>& p);
  void make_lower(const SparseMatrix& A);
  /// The factorisation of lower_ into p.
  template <class T>
  bool factorize_in(Panels<T>& p);
  template <class T>
  void start_panel(Panels<T>& p, int t, const double* a);
  template <class T>
  void start_panels(Panels<T>& p, int s, const double* a);
  template <class T>
  bool factor_diagonal(Panels<T>& p, int s, Work<T>& w);
  template <class T>
  void solve_below(Panels<T>& p, int s, int begin, int end);
  template <class T>
  void scatter_update(Panels<T>& p, int s, Work<T>& w, T* top_copy);
  template <class T>
  void update_columns(Panels<T>& p, int s, int begin, int end, Work<T>& w);
  template <class T>
  void subtract_update(Panels<T>& p, int s, int begin, int end, std::ptrdiff_t ldw, Work<T>& w,
                       T* top_copy);
  template <class T>
  void factorize_split(Panels<T>& p, const double* a);
  template <class T>
  void forward(Panels<T>& p, int s, T* y, T* top_y, Work<T>& w);
  template <class T>
  void backward(Panels<T>& p, int s, T* y, Work<T>& w);
  template <class T>
  void solve_split(Panels<T>& p);
  /// x = A⁻¹ b with the factor in p (b and x may be the same vector).
  template <class T>
  void solve_with(Panels<T>& p, const Eigen::VectorXd& b, Eigen::VectorXd& x);
  bool solve_refined(const Eigen::VectorXd& b, Eigen::VectorXd& x, double enough);
  void pause_float();
  double backward_error(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r);

  const OpenBlasKernels* blas_ = nullptr;  ///< OpenBLAS for the wider updates, or none
  Amalgamation relax_;
  double split_flops_;
  Precision precision_;
  SupernodalStructure st_;
  TreeSplit split_;
  bool splits_ = false;
  std::vector<int> start_begin_;  ///< panels started before s: starts_[start_begin_[s] .. [s + 1])
  std::vector<int> starts_;
  std::vector<int> load_begin_;  ///< A's entries in t's panel: loads_[load_begin_[t] .. [t + 1])
  std::vector<Load> loads_;
  Panels<double> double_;
  Panels<float> float_;
  bool float_factor_ = false;
  double float_pass_accuracy_ = std::numeric_limits<double>::quiet_NaN();
  /// A's lower triangle as last factorised (the panels' loads, the mixed refinement's residuals,
  /// a fallback to double), and ‖A‖∞
  SparseMatrix lower_;
  double a_norm_ = 0;
  Eigen::VectorXd second_half_;  ///< backward_error's sums over the second half of the columns
  Eigen::VectorXd r_, dx_;       ///< mixed: a residual and a correction
  bool mixed_ = false;
  int double_pause_ = 0, pause_length_ = 0;  ///< factorisations left in double; the next pause's
  MixedCounts counts_;
  bool factorized_ = false;
  double pivot_ratio_ = 0;
  SplitSeconds split_seconds_;
  std::string status_;
};

}  // namespace velum
