// OpenBLAS's kernels chosen from the CPU's features. A DYNAMIC_ARCH OpenBLAS (Debian's) picks
// its kernels when it loads, from a table of CPU models it knows: on a newer processor it falls
// back to older kernels (Debian's 0.3.21 runs its SSE3 "Prescott" kernels on an AVX-512 Xeon of
// family 6 model 207, at a quarter of the AVX-512 kernels' dgemm speed). OPENBLAS_CORETYPE
// overrides that choice, but only when it is set before the library loads, that is before
// main() runs: the velum command re-executes itself once with it set.
#pragma once

#include <string>
#include <string_view>

namespace velum {

struct CpuFeatures {
  bool avx512 = false;    ///< AVX-512 F, DQ, BW and VL, with the OS saving the zmm state
  bool avx2_fma = false;  ///< AVX2 and FMA3, likewise
  static CpuFeatures of_this_machine();
};

/// The OPENBLAS_CORETYPE to set, or "" to leave the library as it is: "" when the variable is
/// already set (by the user or the machine's environment: some machines set it on purpose,
/// because some OpenBLAS builds compute wrong results on some processors; never overridden),
/// when no OpenBLAS is loaded (active_core empty) or when its kernels already use AVX2 and FMA;
/// otherwise "SkylakeX" (a CPU with AVX-512) or "Haswell" (AVX2 and FMA).
std::string blas_coretype_to_request(const char* environment_value, std::string_view active_core,
                                     const CpuFeatures& cpu);

/// The kernels the loaded OpenBLAS uses (openblas_get_corename), or "" without OpenBLAS.
std::string openblas_core();

/// OpenBLAS's rank-k update (syrk: C = alpha A Aᵀ + beta C, a triangle of C) and product
/// (gemm: C = alpha A Bᵀ + beta C) in double and float, with the calls that set its thread
/// count, when the loaded OpenBLAS runs AVX-512 kernels (SkylakeX, Cooperlake, SapphireRapids)
/// on a CPU that has AVX-512: there they are faster than Eigen's products for the supernodal
/// Cholesky's larger updates (docs/performance.md), and its Haswell kernels
/// are slower. Null members otherwise (another BLAS, older kernels): all or none are found.
struct OpenBlasKernels {
  template <class T>
  using Syrk = void (*)(const char* uplo, const char* trans, const int* n, const int* k,
                        const T* alpha, const T* a, const int* lda, const T* beta, T* c,
                        const int* ldc);
  template <class T>
  using Gemm = void (*)(const char* transa, const char* transb, const int* m, const int* n,
                        const int* k, const T* alpha, const T* a, const int* lda, const T* b,
                        const int* ldb, const T* beta, T* c, const int* ldc);
  Syrk<double> dsyrk = nullptr;
  Syrk<float> ssyrk = nullptr;
  Gemm<double> dgemm = nullptr;
  Gemm<float> sgemm = nullptr;
  int (*get_threads)() = nullptr;
  void (*set_threads)(int) = nullptr;
  /// C's lower triangle (n x n, column-major, leading dimension ldc) += alpha A Aᵀ, A n x k.
  template <class T>
  void syrk_lower(int n, int k, T alpha, const T* a, int lda, T* c, int ldc) const;
  /// C (m x n) += alpha A Bᵀ, A m x k, B n x k.
  template <class T>
  void gemm_abt(int m, int n, int k, T alpha, const T* a, int lda, const T* b, int ldb, T* c,
                int ldc) const;
  /// Whether these kernels should be used on this CPU (the core's name as
  /// openblas_get_corename gives it).
  static bool worth_it(std::string_view active_core, const CpuFeatures& cpu);
  /// Found once per process (dlsym), the kernels' name read then.
  static const OpenBlasKernels& loaded();
  /// loaded() where its kernels were found, else null (what the dense kernels take).
  static const OpenBlasKernels* found() { return loaded().dsyrk ? &loaded() : nullptr; }
};

/// While one lives, OpenBLAS runs on the calling thread only (its count restored after): the
/// supernodal Cholesky calls it from its own threads.
class SerialOpenBlas {
 public:
  explicit SerialOpenBlas(const OpenBlasKernels& blas);
  ~SerialOpenBlas();
  SerialOpenBlas(const SerialOpenBlas&) = delete;
  SerialOpenBlas& operator=(const SerialOpenBlas&) = delete;

 private:
  const OpenBlasKernels& blas_;
  int threads_ = 0;
};

/// OpenBLAS starts its worker threads when it is loaded, and each spins (sched_yield) for about
/// 0.1 s before it sleeps: while a model is read that is another core's CPU, which a one-thread
/// `velum check` paid for (100 ms against 54). Ends them (the next openblas_set_num_threads or
/// threaded call starts them again); nothing without OpenBLAS.
void stop_idle_blas_threads();

/// To be called first in main(): when blas_coretype_to_request names kernels, sets
/// OPENBLAS_CORETYPE and re-executes /proc/self/exe with the same arguments (the variable, now
/// set, stops a second re-execution). Returns only when nothing was done or exec failed.
void choose_blas_kernels(char** argv);

}  // namespace velum
