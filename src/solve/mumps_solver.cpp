#include "mumps_solver.hpp"

#ifdef VELUM_HAVE_MUMPS
#include <dmumps_c.h>
#ifdef VELUM_DMUMPS_C
// Built beside PETSc: the sequential MUMPS's entry point under a private name, apart from
// PETSc's parallel MUMPS (CMakeLists.txt).
extern "C" void VELUM_DMUMPS_C(DMUMPS_STRUC_C* id);
#define dmumps_c VELUM_DMUMPS_C
#endif

#include <algorithm>
#include <string>
#include <vector>

#include "ordering.hpp"
#include "symmetry.hpp"

namespace velum {
namespace {

// One MUMPS instance of a fixed symmetry: sym = 2 (general symmetric, LDLᵀ with pivoting,
// lower triangle given) or 0 (unsymmetric LU, all entries).
class MumpsInstance {
 public:
  explicit MumpsInstance(int sym) {
    id_.comm_fortran = -987654;  // USE_COMM_WORLD of the sequential MPI stub
    id_.par = 1;
    id_.sym = sym;
    id_.job = -1;
    dmumps_c(&id_);
    id_.icntl[0] = id_.icntl[1] = id_.icntl[2] = -1;  // no output
    id_.icntl[3] = 0;
    id_.icntl[13] = 30;  // ICNTL(14): % workspace for pivoting, doubled on demand
  }
  ~MumpsInstance() {
    id_.job = -2;
    dmumps_c(&id_);
  }
  MumpsInstance(const MumpsInstance&) = delete;
  MumpsInstance& operator=(const MumpsInstance&) = delete;

  bool analyze(const SparseMatrix& A) {
    size_t count = 0;
    for_each_entry(A, [&](int, int, Eigen::Index) { ++count; });
    irn_.clear(), jcn_.clear();
    irn_.reserve(count), jcn_.reserve(count);  // exact: growth would leave up to half unused
    for_each_entry(A, [&](int i, int j, Eigen::Index) {
      irn_.push_back(i + 1);
      jcn_.push_back(j + 1);
    });
    val_.resize(irn_.size());
    id_.n = static_cast<int>(A.rows());
    id_.nnz = static_cast<MUMPS_INT8>(irn_.size());
    id_.irn = irn_.data();
    id_.jcn = jcn_.data();
    // Our own ordering (ICNTL(7) = 1). Debian's sequential MUMPS is built without METIS and
    // asked for it silently uses SCOTCH: at 152k DOFs (Hencky quad4 n = 130) that factor
    // takes 8.8 GFlop and 23.2 M entries against 6.4 GFlop and 19.8 M with this one.
    position_ = nested_dissection(A);
    if (!position_.empty()) {
      for (int& p : position_) ++p;
      id_.perm_in = position_.data();
      id_.icntl[6] = 1;
    } else {
      id_.icntl[6] = 7;  // MUMPS's automatic choice
    }
    id_.job = 1;
    dmumps_c(&id_);
    return id_.infog[0] >= 0;
  }
  // A symmetric matrix is first factorised without pivoting (CNTL(1) = 0) and with a plain
  // diagonal scaling: exact and stable when it is positive definite, and it skips the pivot
  // search with its updates of whole fronts and the iterative scaling (a noticeable share of a
  // large static run). A negative or failed pivot means indefinite: the matrix is
  // factorised again with threshold pivoting, which is then kept for the next 1, 2, 4 ... 64
  // factorisations before no pivoting is tried again.
  bool factorize(const SparseMatrix& A) {
    size_t n = 0;
    for_each_entry(A, [&](int, int, Eigen::Index k) { val_[n++] = A.valuePtr()[k]; });
    id_.a = val_.data();
    if (id_.sym == 2 && pivot_for_ == 0) {
      id_.cntl[0] = 0.0;
      id_.icntl[7] = 1;  // diagonal scaling: all a definite matrix needs, cheaper than 77
      if (factorize_values() && id_.infog[11] == 0) {
        pivot_backoff_ = 1;
        return true;
      }
      pivot_for_ = pivot_backoff_;
      pivot_backoff_ = std::min(2 * pivot_backoff_, 64);
    }
    if (pivot_for_ > 0) --pivot_for_;
    id_.cntl[0] = kPivotThreshold;
    id_.icntl[7] = 77;  // MUMPS's automatic choice of scaling
    return factorize_values();
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    x = b;
    id_.rhs = x.data();
    id_.job = 3;
    dmumps_c(&id_);
    return id_.infog[0] >= 0 && x.allFinite();
  }
  int negative_pivots() const { return id_.sym == 2 && id_.infog[0] >= 0 ? id_.infog[11] : -1; }
  std::string status() const {
    const int e = id_.infog[0], e2 = id_.infog[1];
    if (e >= 0) return {};
    if (e == -10) return "MUMPS: numerically singular matrix";
    if (e == -13) return "MUMPS: out of memory";
    return "MUMPS error INFOG(1) = " + std::to_string(e) + ", INFOG(2) = " + std::to_string(e2);
  }

 private:
  DMUMPS_STRUC_C id_{};
  // The entries given to MUMPS, in one order for analysis and factorisation: all of them, or
  // the lower triangle of a symmetric matrix.
  template <class F>
  void for_each_entry(const SparseMatrix& A, const F& f) const {
    for (int j = 0; j < A.outerSize(); ++j)
      for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k)
        if (id_.sym == 0 || A.innerIndexPtr()[k] >= j) f(A.innerIndexPtr()[k], j, k);
  }

  bool factorize_values() {
    for (int attempt = 0; attempt < 4; ++attempt) {
      id_.job = 2;
      dmumps_c(&id_);
      // -8, -9, -14, -15, -17, -20: a workspace too small for the pivots delayed.
      const int e = id_.infog[0];
      if (e != -8 && e != -9 && e != -14 && e != -15 && e != -17 && e != -20) break;
      id_.icntl[13] *= 2;
    }
    return id_.infog[0] >= 0;
  }

  static constexpr double kPivotThreshold = 0.01;  ///< MUMPS's default for sym = 2
  int pivot_for_ = 0;      ///< factorisations left with pivoting before trying without
  int pivot_backoff_ = 1;  ///< the next such count
  std::vector<MUMPS_INT> irn_, jcn_;
  std::vector<double> val_;
  std::vector<MUMPS_INT> position_;  ///< 1-based pivot position of each equation
};

class Mumps final : public LinearSolver {
 public:
  explicit Mumps(bool known_symmetric) : known_symmetric_(known_symmetric) {}
  std::string_view name() const override { return "mumps"; }
  bool symmetric_only() const override { return known_symmetric_; }
  bool analyze(const SparseMatrix& A) override {
    if (!known_symmetric_) check_.map(A);
    sym_.reset();
    lu_.reset();
    return true;  // each instance analyses when it is first needed
  }
  bool factorize(const SparseMatrix& A) override {
    const bool sym = known_symmetric_ || check_.symmetric(A);
    auto& inst = sym ? sym_ : lu_;
    if (!inst) {
      inst = std::make_unique<MumpsInstance>(sym ? 2 : 0);
      if (!inst->analyze(A)) {
        active_ = inst.get();
        return false;
      }
    }
    (sym ? lu_ : sym_).reset();  // one factorisation in memory at a time
    active_ = inst.get();
    return active_->factorize(A);
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return active_ && active_->solve(b, x);
  }
  std::string status() const override { return active_ ? active_->status() : std::string(); }
  int negative_pivots() const override { return active_ ? active_->negative_pivots() : -1; }

 private:
  bool known_symmetric_;
  SymmetryCheck check_;
  std::unique_ptr<MumpsInstance> sym_, lu_;
  MumpsInstance* active_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> make_mumps_solver(bool symmetric) {
  return std::make_unique<Mumps>(symmetric);
}
bool have_mumps() {
  return true;
}

}  // namespace velum

#else

namespace velum {
std::unique_ptr<LinearSolver> make_mumps_solver(bool) {
  return nullptr;
}
bool have_mumps() {
  return false;
}
}  // namespace velum

#endif
