#include "velum/solve/petsc_solver.hpp"

#include <stdexcept>

#include "velum/parallel/processes.hpp"

#ifdef VELUM_HAVE_PETSC
#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "symmetry.hpp"

namespace velum {
namespace {

// Columns orthonormalised by modified Gram-Schmidt, twice (a mode that depends on the others
// is dropped): PETSc's MatNullSpaceCreate wants orthonormal vectors.
// Over several processes' local equations, the dots of the layout.
MatX orthonormal_columns(const MatX& modes, const EquationLayout* layout) {
  const bool several = layout && layout->distributed();
  auto dot = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return several ? layout->dot(a, b) : a.dot(b);
  };
  auto norm = [&](const Eigen::VectorXd& a) { return several ? layout->norm(a) : a.norm(); };
  MatX q(modes.rows(), 0);
  for (Eigen::Index j = 0; j < modes.cols(); ++j) {
    Eigen::VectorXd v = modes.col(j);
    const double n0 = norm(v);
    if (!(n0 > 0)) continue;
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index k = 0; k < q.cols(); ++k) {
        const Eigen::VectorXd qk = q.col(k);
        v -= dot(qk, v) * qk;
      }
    if (norm(v) <= 1e-10 * n0) continue;
    q.conservativeResize(Eigen::NoChange, q.cols() + 1);
    q.col(q.cols() - 1) = v / norm(v);
  }
  return q;
}

class PetscSolver final : public LinearSolver {
 public:
  explicit PetscSolver(const PetscSolverSettings& s) : settings_(s) {
    processes::ensure_started();
    comm_ = PETSC_COMM_WORLD;
    // PETSc's options database is global: cleared, so that one solver's options never leak
    // into the next; then the defaults, then the model's options over them (the last wins).
    PetscOptionsClear(nullptr);
    PetscOptionsInsertString(nullptr, "-mat_mumps_icntl_14 50 -mat_mumps_icntl_13 1");
    if (!s.options.empty() && PetscOptionsInsertString(nullptr, s.options.c_str()) != 0)
      throw std::invalid_argument("analysis.petsc_options: PETSc cannot read '" + s.options + "'");
    PetscBool set = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, "-pc_type", &set);
    user_pc_ = set == PETSC_TRUE;
    PetscOptionsHasName(nullptr, nullptr, "-ksp_pc_side", &set);
    user_side_ = set == PETSC_TRUE;
    PetscOptionsHasName(nullptr, nullptr, "-pc_factor_mat_solver_type", &set);
    user_factor_ = set == PETSC_TRUE;
  }
  ~PetscSolver() override { release(); }
  PetscSolver(const PetscSolver&) = delete;
  PetscSolver& operator=(const PetscSolver&) = delete;

  std::string_view name() const override { return name_; }
  bool symmetric_only() const override { return false; }
  std::string status() const override { return status_; }
  int negative_pivots() const override { return negative_; }

  // A is this process's share of the matrix (on one process, the whole of it): every entry
  // of it is added (ADD_VALUES) into the distributed matrix, rows owned elsewhere included
  // (PETSc sends those at assembly), column by column straight from A's storage (no copy of
  // the share: it would cost 20 bytes per entry, as much as PETSc's matrix). The
  // preallocation is the union of the shares' patterns.
  bool analyze(const SparseMatrix& A) override {
    release();
    status_.clear();
    const EquationLayout* layout = settings_.layout;
    several_ = layout && layout->distributed();
    const int n = several_ ? static_cast<int>(layout->total()) : static_cast<int>(A.rows());
    int size = 1, rank = 0;
    MPI_Comm_size(comm_, &size);
    MPI_Comm_rank(comm_, &rank);
    bs_ = settings_.block_size > 1 && n % settings_.block_size == 0 ? settings_.block_size : 1;
    if (several_) {
      // The layout's rows (whole nodes where the equations come three to a node, as below);
      // the share's local indices map to global ones.
      lo_ = static_cast<int>(layout->first());
      hi_ = lo_ + layout->owned();
      if (bs_ > 1 && (lo_ % bs_ != 0 || hi_ % bs_ != 0)) bs_ = 1;
      global_.resize(static_cast<size_t>(layout->local()));
      for (int i = 0; i < layout->local(); ++i)
        global_[static_cast<size_t>(i)] = static_cast<PetscInt>(layout->global(i));
    } else {
      // Contiguous rows, whole blocks, as even as PETSc's own split.
      lo_ = static_cast<int>(processes::range_start(n, bs_, size, rank));
      hi_ = static_cast<int>(processes::range_start(n, bs_, size, rank + 1));
    }
    const int local = hi_ - lo_;
    Mat pre = nullptr;
    const bool made = ok(MatCreate(comm_, &A_), "MatCreate") &&
                      ok(MatSetSizes(A_, local, local, n, n), "MatSetSizes") &&
                      ok(MatSetType(A_, MATAIJ), "MatSetType") &&
                      ok(MatSetBlockSize(A_, bs_), "MatSetBlockSize") &&
                      ok(MatCreate(comm_, &pre), "MatCreate") &&
                      ok(MatSetSizes(pre, local, local, n, n), "MatSetSizes") &&
                      ok(MatSetType(pre, MATPREALLOCATOR), "MatSetType") &&
                      ok(MatSetBlockSize(pre, bs_), "MatSetBlockSize") &&
                      ok(MatSetUp(pre), "MatSetUp") && add_share(pre, A, false) && assemble(pre) &&
                      ok(MatPreallocatorPreallocate(pre, PETSC_TRUE, A_), "preallocation");
    if (pre) MatDestroy(&pre);
    if (!made ||
        !ok(MatSetOption(A_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption") ||
        !ok(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs") || !ok(VecDuplicate(b_, &r_), "Vec") ||
        (!several_ && !ok(VecScatterCreateToAll(x_, &to_all_, &x_all_), "VecScatterCreateToAll")))
      return false;
    if (!ok(KSPCreate(comm_, &ksp_), "KSPCreate") ||
        !ok(KSPSetOperators(ksp_, A_, A_), "KSPSetOperators") ||
        !ok(KSPSetType(ksp_, KSPPREONLY), "KSPSetType") || !ok(KSPGetPC(ksp_, &pc_), "KSPGetPC") ||
        !ok(PCSetType(pc_, PCLU), "PCSetType") ||
        !ok(KSPSetTolerances(ksp_, 1e-10, 1e-300, PETSC_DEFAULT, 1000), "KSPSetTolerances") ||
        !ok(KSPSetFromOptions(ksp_), "KSPSetFromOptions"))
      return false;
    if (!user_factor_) PCFactorSetMatSolverType(pc_, MATSOLVERMUMPS);
    KSPType kt;
    PCType pt;
    KSPGetType(ksp_, &kt);
    PCGetType(pc_, &pt);
    direct_ = std::string(kt) == KSPPREONLY;
    factor_kind_ = std::string(pt);
    if (!direct_) {
      if (!user_side_) KSPSetPCSide(ksp_, PC_RIGHT);
      if (settings_.near_null_space && !set_near_null_space(static_cast<int>(A.rows())))
        return false;
    }
    name_ = direct_ ? fmt::format("petsc ({})", user_pc_ ? factor_kind_ : "mumps")
                    : fmt::format("petsc ({} + {})", kt, pt);
    return true;
  }

  bool factorize(const SparseMatrix& A) override {
    negative_ = -1;
    status_.clear();
    if (!A_) return false;
    // Numerically symmetric: max |a_ij − a_ji| <= 1e-10 max |a_ij| (as `auto`), judged on the
    // summed matrix; the same answer on every process. A − Aᵀ, the sum of the shares' a_ij −
    // a_ji, is assembled first into A_ itself (no second matrix: its pattern, the union of
    // the shares' structurally symmetric patterns, holds Aᵀ's), then A over it.
    bool symmetric = false;
    PetscReal dmax = 0;
    if (direct_ && !user_pc_ &&
        (!ok(MatZeroEntries(A_), "MatZeroEntries") || !add_share(A_, A, false) ||
         !add_share(A_, A, true) || !assemble(A_) || !max_abs(A_, dmax)))
      return false;
    if (!ok(MatZeroEntries(A_), "MatZeroEntries") || !add_share(A_, A, false) || !assemble(A_))
      return false;
    MatNorm(A_, NORM_FROBENIUS, &anorm_);
    if (direct_ && !user_pc_) {
      PetscReal amax = 0;
      if (!max_abs(A_, amax)) return false;
      symmetric = dmax <= SymmetryCheck::kTolerance * amax;
    }
    if (direct_ && !user_pc_) {
      const char* want = symmetric ? PCCHOLESKY : PCLU;
      if (factor_kind_ != want) {  // a new factor type: its symbolic analysis is redone
        if (!ok(PCSetType(pc_, want), "PCSetType")) return false;
        if (!user_factor_) PCFactorSetMatSolverType(pc_, MATSOLVERMUMPS);
        factor_kind_ = want;
      }
    }
    // New values on the same pattern: KSPSetOperators again, or KSPSetUp returns at once and
    // the factorisation happens only inside KSPSolve (its status and inertia read here would
    // be those of the previous matrix).
    if (!ok(KSPSetOperators(ksp_, A_, A_), "KSPSetOperators") || !ok(KSPSetUp(ksp_), "KSPSetUp"))
      return false;
    PCFailedReason failed = PC_NOERROR;
    PCGetFailedReasonRank(pc_, &failed);
    int bad = failed != PC_NOERROR ? 1 : 0, any = 0;
    MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm_);
    if (direct_) {
      Mat F = nullptr;
      if (PCFactorGetMatrix(pc_, &F) == 0 && F) {
        MatSolverType type = nullptr;
        MatFactorGetSolverType(F, &type);
        if (type && std::string(type) == MATSOLVERMUMPS) {
          PetscInt info1 = 0, neg = -1;
          MatMumpsGetInfog(F, 1, &info1);
          if (info1 < 0) {
            status_ = fmt::format("MUMPS (through PETSc): INFOG(1) = {}", info1);
            return false;
          }
          // The inertia of LDLᵀ (Sylvester); MUMPS counts the root's negative pivots too only
          // with ICNTL(13) = 1 (no ScaLAPACK on the root), set below for Cholesky.
          if (factor_kind_ == PCCHOLESKY) {
            if (MatGetInertia(F, &neg, nullptr, nullptr) != 0) neg = -1;
          }
          negative_ = static_cast<int>(neg);
        }
        MatFactorError err = MAT_FACTOR_NOERROR;
        MatFactorGetError(F, &err);
        if (err != MAT_FACTOR_NOERROR) any = 1;
      }
    }
    if (any) {
      status_ = fmt::format("PETSc: the preconditioner ({}) failed to set up (reason {})",
                            factor_kind_, static_cast<int>(failed));
      negative_ = -1;
      return false;
    }
    return true;
  }

  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    if (!A_) return false;
    PetscScalar* bb = nullptr;
    if (!ok(VecGetArray(b_, &bb), "VecGetArray")) return false;
    // Several processes: b's owned entries are the first (the local equations).
    const int from = several_ ? 0 : lo_;
    std::copy(b.data() + from, b.data() + from + (hi_ - lo_), bb);
    VecRestoreArray(b_, &bb);
    if (!ok(KSPSolve(ksp_, b_, x_), "KSPSolve")) return false;
    KSPConvergedReason reason;
    KSPGetConvergedReason(ksp_, &reason);
    if (reason < 0) {
      PetscInt its = 0;
      KSPGetIterationNumber(ksp_, &its);
      status_ = fmt::format("PETSc: {} did not converge ({}, {} iterations)", name_,
                            KSPConvergedReasons[reason], its);
      return false;
    }
    // The true residual: a left-preconditioned GMRES has reported convergence with ‖b − Ax‖
    // of 7 (issue 18); a direct solve of a nearly singular matrix can return garbage.
    PetscReal bnorm = 0, rnorm = 0;
    MatMult(A_, x_, r_);
    VecAYPX(r_, -1.0, b_);
    VecNorm(b_, NORM_2, &bnorm);
    VecNorm(r_, NORM_2, &rnorm);
    PetscReal rtol = 0, atol = 0, dtol = 0;
    PetscInt maxit = 0;
    KSPGetTolerances(ksp_, &rtol, &atol, &dtol, &maxit);
    // A direct solve is judged by its backward error (ε ‖A‖ ‖x‖ is what a stable
    // factorisation leaves; a nearly singular A legitimately leaves more than ε ‖b‖).
    PetscReal xnorm = 0;
    VecNorm(x_, NORM_2, &xnorm);
    const double allowed =
        direct_ ? 1e-8 * bnorm + 1e-9 * anorm_ * xnorm : std::max(10 * rtol * bnorm, 10 * atol);
    if (!std::isfinite(rnorm) || rnorm > allowed) {
      status_ = fmt::format("PETSc: {} returned a solution with |b - Ax| = {:.3g} (|b| = {:.3g})",
                            name_, rnorm, bnorm);
      return false;
    }
    if (several_) {  // the owned entries from PETSc, the ghosts from their owners
      const PetscScalar* xo = nullptr;
      VecGetArrayRead(x_, &xo);
      x.resize(b.size());
      std::copy(xo, xo + (hi_ - lo_), x.data());
      VecRestoreArrayRead(x_, &xo);
      settings_.layout->update_ghosts(x);
      int finite = x.allFinite() ? 1 : 0, all = 0;
      MPI_Allreduce(&finite, &all, 1, MPI_INT, MPI_MIN, comm_);
      return all != 0;
    }
    if (!ok(VecScatterBegin(to_all_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "scatter") ||
        !ok(VecScatterEnd(to_all_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "scatter"))
      return false;
    const PetscScalar* xa = nullptr;
    VecGetArrayRead(x_all_, &xa);
    x.resize(b.size());
    std::copy(xa, xa + b.size(), x.data());
    VecRestoreArrayRead(x_all_, &xa);
    return x.allFinite();
  }

 private:
  bool ok(PetscErrorCode code, const char* what) {
    if (code == 0) return true;
    const char* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    status_ = fmt::format("PETSc: {} failed: {}", what, text ? text : "error");
    return false;
  }

  // Adds this process's share A into M column by column (entry (i, j) of A to row i), or,
  // `transposed`, minus its transpose (entry (i, j) of A, negated, to row j). Not assembled.
  bool add_share(Mat M, const SparseMatrix& A, bool transposed) {
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* v = A.valuePtr();
    for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
      const int first = outer[j], count = outer[j + 1] - first;
      if (count == 0) continue;
      index_.assign(inner + first, inner + first + count);
      PetscInt col = static_cast<PetscInt>(j);
      if (several_) {
        for (PetscInt& i : index_) i = global_[static_cast<size_t>(i)];
        col = global_[static_cast<size_t>(j)];
      }
      PetscErrorCode code = 0;
      if (!transposed) {
        code = MatSetValues(M, count, index_.data(), 1, &col, v + first, ADD_VALUES);
      } else {
        negated_.resize(static_cast<size_t>(count));
        for (int k = 0; k < count; ++k) negated_[static_cast<size_t>(k)] = -v[first + k];
        code = MatSetValues(M, 1, &col, count, index_.data(), negated_.data(), ADD_VALUES);
      }
      if (!ok(code, "MatSetValues")) return false;
    }
    return true;
  }

  bool assemble(Mat M) {
    return ok(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin") &&
           ok(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  }

  // The largest |a_ij| of the assembled matrix, over every process.
  bool max_abs(Mat A, PetscReal& amax) {
    PetscReal mine = 0;
    auto scan = [&](Mat M) {
      MatInfo info;
      const PetscScalar* a = nullptr;
      if (!ok(MatGetInfo(M, MAT_LOCAL, &info), "MatGetInfo") ||
          !ok(MatSeqAIJGetArrayRead(M, &a), "MatSeqAIJGetArrayRead"))
        return false;
      const auto nz = static_cast<PetscInt>(info.nz_used);
      for (PetscInt k = 0; k < nz; ++k) mine = std::max(mine, PetscAbsScalar(a[k]));
      MatSeqAIJRestoreArrayRead(M, &a);
      return true;
    };
    PetscBool mpi = PETSC_FALSE;
    PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A), MATMPIAIJ, &mpi);
    if (mpi == PETSC_TRUE) {
      Mat diagonal = nullptr, off = nullptr;
      if (!ok(MatMPIAIJGetSeqAIJ(A, &diagonal, &off, nullptr), "MatMPIAIJGetSeqAIJ") ||
          !scan(diagonal) || !scan(off))
        return false;
    } else if (!scan(A)) {
      return false;
    }
    return MPI_Allreduce(&mine, &amax, 1, MPIU_REAL, MPI_MAX, comm_) == MPI_SUCCESS;
  }

  bool set_near_null_space(int n) {
    const MatX modes = settings_.near_null_space();
    if (modes.rows() != n) return true;  // none for these equations
    const MatX q = orthonormal_columns(modes, several_ ? settings_.layout : nullptr);
    std::vector<Vec> vecs(q.cols());
    for (Eigen::Index k = 0; k < q.cols(); ++k) {
      VecDuplicate(x_, &vecs[k]);
      PetscScalar* a = nullptr;
      VecGetArray(vecs[k], &a);
      const int from = several_ ? 0 : lo_;  // several: the owned rows come first
      for (int i = lo_; i < hi_; ++i) a[i - lo_] = q(i - lo_ + from, k);
      VecRestoreArray(vecs[k], &a);
    }
    MatNullSpace space;
    const bool done = ok(MatNullSpaceCreate(comm_, PETSC_FALSE, static_cast<PetscInt>(vecs.size()),
                                            vecs.data(), &space),
                         "MatNullSpaceCreate") &&
                      ok(MatSetNearNullSpace(A_, space), "MatSetNearNullSpace");
    if (done) MatNullSpaceDestroy(&space);
    for (Vec& v : vecs) VecDestroy(&v);
    return done;
  }

  void release() {
    if (ksp_) KSPDestroy(&ksp_);
    if (to_all_) VecScatterDestroy(&to_all_);
    if (x_all_) VecDestroy(&x_all_);
    for (Vec* v : {&x_, &b_, &r_})
      if (*v) VecDestroy(v);
    if (A_) MatDestroy(&A_);
    ksp_ = nullptr, pc_ = nullptr, A_ = nullptr, to_all_ = nullptr;
  }

  PetscSolverSettings settings_;
  MPI_Comm comm_;
  bool user_pc_ = false, user_side_ = false, user_factor_ = false, direct_ = true;
  std::string name_ = "petsc", factor_kind_, status_;
  int bs_ = 1, lo_ = 0, hi_ = 0, negative_ = -1;
  bool several_ = false;          // local equations (settings_.layout)
  std::vector<PetscInt> global_;  // several: global equation of each local one
  PetscReal anorm_ = 0;
  std::vector<PetscInt> index_;       // add_share's row (column) indices of one column
  std::vector<PetscScalar> negated_;  // add_share's values of one column, negated
  Mat A_ = nullptr;
  Vec x_ = nullptr, b_ = nullptr, r_ = nullptr, x_all_ = nullptr;
  VecScatter to_all_ = nullptr;
  KSP ksp_ = nullptr;
  PC pc_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> make_petsc_solver(const PetscSolverSettings& settings) {
  return std::make_unique<PetscSolver>(settings);
}

}  // namespace velum

#else

namespace velum {

std::unique_ptr<LinearSolver> make_petsc_solver(const PetscSolverSettings&) {
  throw std::runtime_error(
      "linear_solver petsc: this build has no PETSc (install petsc-dev and rebuild with "
      "VELUM_WITH_PETSC=ON)");
}

}  // namespace velum

#endif
