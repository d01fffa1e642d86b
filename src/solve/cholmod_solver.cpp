#include "cholmod_solver.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <Eigen/CholmodSupport>

#include <stdexcept>

#include "eigen_solver.hpp"
#include "symmetry.hpp"

namespace velum {
namespace {

// CHOLMOD 3.0 (SuiteSparse 5.12) runs loops of its supernodal factorisation in OpenMP regions
// with num_threads(CHOLMOD_OMP_NUM_THREADS), a constant 4, whatever the program's thread count:
// with --threads 1 the three extra threads spin in libgomp and the kernel, against the run's
// own work, on a machine with fewer cores than that (docs/performance.md). Those loops copy
// and clear; the BLAS (dgemm, dsyrk), which does the work, has its own threads (--threads).
// While CHOLMOD runs, no
// OpenMP region may be active (max-active-levels 0): its regions run on the calling thread.
class SerialOpenMp {
 public:
  SerialOpenMp() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMp() { omp_set_max_active_levels(levels_); }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int levels_;
};

class Cholmod final : public EigenSolver<Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>> {
 public:
  // A non-positive pivot is reported through the status (and `auto` falls back to LU), not
  // printed on the user's console by CHOLMOD itself.
  // METIS nested dissection: on membrane meshes slightly faster factorisations and less fill
  // than CHOLMOD's default AMD, for a dearer analysis made once per run (bench BM_Factorize).
  // check_symmetry: CHOLMOD reads the lower triangle only, so a matrix chosen by the user is
  // checked at every factorisation (one pass over the entries, against a factorisation's many):
  // an unsymmetric one (a follower pressure on a surface with a free edge, drag) would be
  // factorised as a different, symmetric matrix. `auto` checks before it calls CHOLMOD.
  explicit Cholmod(bool check_symmetry = true)
      : EigenSolver("cholmod", true), check_symmetry_(check_symmetry) {
    impl_.cholmod().print = 0;
    impl_.cholmod().nmethods = 1;
    impl_.cholmod().method[0].ordering = CHOLMOD_METIS;
  }
  bool analyze(const SparseMatrix& A) override {
    if (check_symmetry_) check_.map(A);
    SerialOpenMp serial;
    return EigenSolver::analyze(A);
  }
  bool factorize(const SparseMatrix& A) override {
    if (check_symmetry_) {
      const double asym = check_.asymmetry(A);
      if (!(asym <= SymmetryCheck::kTolerance))
        throw std::invalid_argument(fmt::format(
            "linear_solver: cholmod factorises symmetric matrices only (it reads the lower "
            "triangle), but this Jacobian is unsymmetric (max |a_ij - a_ji| = {:.2e} max "
            "|a_ij|; a follower pressure on a surface with a free edge or drag make it so): "
            "use linear_solver: auto, klu, umfpack or mumps",
            asym));
    }
    SerialOpenMp serial;
    impl_.factorize(A);
    // CHOLMOD reports a non-positive pivot through its common status, not through info().
    factorized_ = impl_.info() == Eigen::Success && impl_.cholmod().status == CHOLMOD_OK;
    return factorized_;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    SerialOpenMp serial;
    return EigenSolver::solve(b, x);
  }
  int negative_pivots() const override { return factorized_ ? 0 : -1; }  // definite

 private:
  bool check_symmetry_;
  SymmetryCheck check_;
  bool factorized_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> make_cholmod_solver(bool check_symmetry) {
  return std::make_unique<Cholmod>(check_symmetry);
}

}  // namespace velum
