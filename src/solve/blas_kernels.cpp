#include "velum/solve/blas_kernels.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <type_traits>

namespace velum {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool one_of(std::string_view core, std::initializer_list<std::string_view> names) {
  return std::find(names.begin(), names.end(), core) != names.end();
}

}  // namespace

CpuFeatures CpuFeatures::of_this_machine() {
  CpuFeatures f;
#if defined(__x86_64__) || defined(__i386__)
  // libgcc's feature bits include the OS check (XGETBV) for the AVX and AVX-512 states.
  __builtin_cpu_init();
  f.avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
  f.avx2_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
  return f;
}

std::string blas_coretype_to_request(const char* environment_value, std::string_view active_core,
                                     const CpuFeatures& cpu) {
  if (environment_value != nullptr || active_core.empty()) return {};
  const std::string core = lower(active_core);
  // OpenBLAS's x86-64 cores whose double-precision kernels use 256-bit or 512-bit FMA. Once
  // there, nothing is changed: with MUMPS's LDLᵀ on an AMD EPYC (Zen 5) the SkylakeX kernels
  // gave no gain over Haswell's (a faster dgemm, a slower dtrsm: docs/performance.md); the
  // fallback to SSE3 kernels is what costs a large share of the run.
  if (one_of(core, {"haswell", "zen", "skylakex", "cooperlake", "sapphirerapids"})) return {};
  if (cpu.avx512) return "SkylakeX";
  if (cpu.avx2_fma) return "Haswell";
  return {};
}

std::string openblas_core() {
  using CoreName = char* (*)();
  auto* name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* core = name ? name() : nullptr;
  return core ? core : "";
}

bool OpenBlasKernels::worth_it(std::string_view active_core, const CpuFeatures& cpu) {
  return cpu.avx512 && one_of(lower(active_core), {"skylakex", "cooperlake", "sapphirerapids"});
}

void stop_idle_blas_threads() {
  // OpenBLAS's own, the function it registers for fork (not in its header).
  if (auto* shutdown = reinterpret_cast<void (*)()>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_")))
    shutdown();
}

const OpenBlasKernels& OpenBlasKernels::loaded() {
  static const OpenBlasKernels blas = [] {
    OpenBlasKernels b;
    if (!worth_it(openblas_core(), CpuFeatures::of_this_machine())) return b;
    // The kernels from the library that named its kernels: the first dsyrk_ loaded could be
    // another BLAS's (libblas.so.3 is an alternative that may be the reference BLAS).
    Dl_info info{};
    void* core_name = dlsym(RTLD_DEFAULT, "openblas_get_corename");
    if (!core_name || !dladdr(core_name, &info) || !info.dli_fname) return b;
    void* library = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
    if (!library) return b;  // kept open: its functions are used until the process ends
    OpenBlasKernels found;
    found.dsyrk = reinterpret_cast<Syrk<double>>(dlsym(library, "dsyrk_"));
    found.ssyrk = reinterpret_cast<Syrk<float>>(dlsym(library, "ssyrk_"));
    found.dgemm = reinterpret_cast<Gemm<double>>(dlsym(library, "dgemm_"));
    found.sgemm = reinterpret_cast<Gemm<float>>(dlsym(library, "sgemm_"));
    found.get_threads = reinterpret_cast<int (*)()>(dlsym(library, "openblas_get_num_threads"));
    found.set_threads = reinterpret_cast<void (*)(int)>(dlsym(library, "openblas_set_num_threads"));
    // Without the thread calls its own threads could run inside ours: none is used then.
    if (found.dsyrk && found.ssyrk && found.dgemm && found.sgemm && found.get_threads &&
        found.set_threads)
      b = found;
    return b;
  }();
  return blas;
}

template <class T>
void OpenBlasKernels::syrk_lower(int n, int k, T alpha, const T* a, int lda, T* c, int ldc) const {
  const T one = 1;  // β = 1: β = 0 would cost a pass of its own over C
  if constexpr (std::is_same_v<T, double>)
    dsyrk("L", "N", &n, &k, &alpha, a, &lda, &one, c, &ldc);
  else
    ssyrk("L", "N", &n, &k, &alpha, a, &lda, &one, c, &ldc);
}

template <class T>
void OpenBlasKernels::gemm_abt(int m, int n, int k, T alpha, const T* a, int lda, const T* b,
                               int ldb, T* c, int ldc) const {
  const T one = 1;
  if constexpr (std::is_same_v<T, double>)
    dgemm("N", "T", &m, &n, &k, &alpha, a, &lda, b, &ldb, &one, c, &ldc);
  else
    sgemm("N", "T", &m, &n, &k, &alpha, a, &lda, b, &ldb, &one, c, &ldc);
}

template void OpenBlasKernels::syrk_lower(int, int, double, const double*, int, double*, int) const;
template void OpenBlasKernels::syrk_lower(int, int, float, const float*, int, float*, int) const;
template void OpenBlasKernels::gemm_abt(int, int, int, double, const double*, int, const double*,
                                        int, double*, int) const;
template void OpenBlasKernels::gemm_abt(int, int, int, float, const float*, int, const float*, int,
                                        float*, int) const;

SerialOpenBlas::SerialOpenBlas(const OpenBlasKernels& blas) : blas_(blas) {
  if (!blas_.dsyrk) return;
  threads_ = blas_.get_threads();
  if (threads_ != 1) blas_.set_threads(1);
}

SerialOpenBlas::~SerialOpenBlas() {
  if (blas_.dsyrk && threads_ > 1) blas_.set_threads(threads_);
}

void choose_blas_kernels(char** argv) {
  const std::string want = blas_coretype_to_request(
      std::getenv("OPENBLAS_CORETYPE"), openblas_core(), CpuFeatures::of_this_machine());
  if (want.empty() || argv == nullptr || argv[0] == nullptr) return;
  if (setenv("OPENBLAS_CORETYPE", want.c_str(), 0) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");  // exec failed: go on with the kernels loaded
}

}  // namespace velum
