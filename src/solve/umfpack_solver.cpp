#include "umfpack_solver.hpp"

#include <Eigen/UmfPackSupport>

#include <string>

#include "eigen_solver.hpp"

namespace velum {
namespace {

// Eigen's UmfPackLU keeps the numeric factorisation's return code protected (its accessor
// asserts on a factorisation that failed to allocate): expose it.
class UmfPackLUWithStatus : public Eigen::UmfPackLU<SparseMatrix> {
 public:
  int return_code() const { return static_cast<int>(m_fact_errorCode); }
};

class UmfPack final : public EigenSolver<UmfPackLUWithStatus> {
 public:
  std::string status() const override {
    // UMFPACK_WARNING_singular_matrix (1) versus out of memory (-1) and the like.
    const int code = impl_.return_code();
    return code == UMFPACK_OK                        ? std::string()
           : code == UMFPACK_WARNING_singular_matrix ? "UMFPACK: singular matrix"
           : code == UMFPACK_ERROR_out_of_memory     ? "UMFPACK: out of memory (status -1)"
                                                     : "UMFPACK status " + std::to_string(code);
  }
  // No iterative refinement (UMFPACK_IRSTEP = 0; UMFPACK's default is up to 2 steps): Newton
  // corrects what a step of refinement would, and a refined solve costs a residual pass and a
  // second solve, several times the solve itself, for a linear residual that Newton does not
  // need.
  // METIS ordering: faster factorisations than the default AMD on membrane meshes (bench
  // BM_Factorize), for a dearer analysis made once per run.
  UmfPack() : EigenSolver("umfpack", false) {
    impl_.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
    impl_.umfpackControl()(UMFPACK_IRSTEP) = 0;
  }
};

}  // namespace

std::unique_ptr<LinearSolver> make_umfpack_solver() {
  return std::make_unique<UmfPack>();
}

}  // namespace velum
