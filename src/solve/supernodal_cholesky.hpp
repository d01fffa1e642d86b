// A supernodal Cholesky factorisation (LLᵀ) for symmetric positive definite matrices (the
// statics of a prestressed membrane, Hencky's problem): the symbolic analysis of the supernodal
// LU (supernodes.hpp) with L's panels only, dense kernels (Eigen; OpenBLAS's dsyrk for the
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
#pragma once

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

  explicit SupernodalCholesky(const Amalgamation& relax = {}, double split_flops = kSplitFlops)
      : relax_(relax), split_flops_(split_flops) {}
  std::string_view name() const override { return "supernodal-cholesky"; }
  bool symmetric_only() const override { return true; }
  bool analyze(const SparseMatrix& A) override;
  /// Reads the lower triangle of A (and the upper within diagonal blocks: A must be symmetric).
  bool factorize(const SparseMatrix& A) override;
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
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

 private:
  struct Work {  ///< one thread's
    std::vector<double> update, gather;
    std::vector<int> runs;  ///< a scatter's runs of contiguous rows
    double smallest = 0, largest = 0;
    bool failed = false;
    std::string status;
    /// Sized for updates of up to `most_below` rows (first call after an analysis only).
    void make(int most_below) {
      const std::size_t mb = static_cast<std::size_t>(std::max(most_below, 1));
      if (runs.size() == mb + 1) return;
      update.assign(mb * mb, 0.0);
      gather.assign(mb, 0.0);
      runs.assign(mb + 1, 0);
    }
  };

  using Load = SupernodalStructure::Load;
  bool plan_panels();
  void first_touch();
  void start_panel(int t, const double* a);
  void start_panels(int s, const SparseMatrix& A);
  bool factor_diagonal(int s, Work& w);
  void solve_below(int s, int begin, int end);
  void scatter_update(int s, Work& w, double* top_copy);
  void update_columns(int s, int begin, int end, Work& w);
  void subtract_update(int s, int begin, int end, std::ptrdiff_t ldw, Work& w, double* top_copy);
  void factorize_split(const SparseMatrix& A);
  void forward(int s, double* y, double* top_y, Work& w);
  void backward(int s, double* y, Work& w);
  void solve_split();

  const OpenBlasSyrk* blas_ = nullptr;  ///< OpenBLAS's dsyrk for the wider updates, or none
  Amalgamation relax_;
  double split_flops_;
  SupernodalStructure st_;
  TreeSplit split_;
  bool splits_ = false;
  std::vector<int> start_begin_;  ///< panels started before s: starts_[start_begin_[s] .. [s + 1])
  std::vector<int> starts_;
  std::vector<int> load_begin_;  ///< A's entries in t's panel: loads_[load_begin_[t] .. [t + 1])
  std::vector<Load> loads_;
  HugePageArray values_, top_copy_;  ///< the L panels; the top's panels' copy (tree_split.hpp)
  std::vector<double> y_, top_y_;
  std::vector<Work> work_;
  bool factorized_ = false;
  double pivot_ratio_ = 0;
  SplitSeconds split_seconds_;
  std::string status_;
};

}  // namespace velum
