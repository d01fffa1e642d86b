// Which OpenBLAS kernels the velum command asks for (blas_kernels.hpp): never against a setting
// of the user or the machine, never without OpenBLAS, only when the loaded kernels are older
// than AVX2 on a CPU that has it.
#include "velum/solve/blas_kernels.hpp"

#include <gtest/gtest.h>

namespace velum {
namespace {

TEST(BlasKernels, ChosenFromTheCpuOnlyWhenNobodyChose) {
  const CpuFeatures avx512{true, true}, avx2{false, true}, sse{false, false};
  // Debian's 0.3.21 on a processor it does not know: Prescott (SSE3) kernels.
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Prescott", avx512), "SkylakeX");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Prescott", avx2), "Haswell");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Sandybridge", avx2), "Haswell");
  // Already AVX2 kernels or wider (SkylakeX's were no faster with MUMPS on an AVX-512 EPYC).
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Haswell", avx512), "");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Cooperlake", avx512), "");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "SkylakeX", avx512), "");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Zen", avx2), "");
  EXPECT_EQ(blas_coretype_to_request(nullptr, "Prescott", sse), "");
  // A setting of the user or the environment, even empty or narrower, is kept.
  EXPECT_EQ(blas_coretype_to_request("Haswell", "Haswell", avx512), "");
  EXPECT_EQ(blas_coretype_to_request("Prescott", "Prescott", avx512), "");
  EXPECT_EQ(blas_coretype_to_request("", "Prescott", avx512), "");
  // No OpenBLAS (another BLAS behind libblas.so.3): nothing to set.
  EXPECT_EQ(blas_coretype_to_request(nullptr, "", avx512), "");
}

TEST(BlasKernels, OpenBlasKernelsOnlyWithAvx512Kernels) {
  const CpuFeatures avx512{true, true}, avx2{false, true};
  EXPECT_TRUE(OpenBlasKernels::worth_it("SkylakeX", avx512));
  EXPECT_TRUE(OpenBlasKernels::worth_it("Cooperlake", avx512));
  EXPECT_TRUE(OpenBlasKernels::worth_it("SapphireRapids", avx512));
  // Haswell's (AVX2) dsyrk is slower than Eigen's product; older kernels more so.
  EXPECT_FALSE(OpenBlasKernels::worth_it("Haswell", avx512));
  EXPECT_FALSE(OpenBlasKernels::worth_it("Zen", avx512));
  EXPECT_FALSE(OpenBlasKernels::worth_it("Prescott", avx512));
  EXPECT_FALSE(OpenBlasKernels::worth_it("SkylakeX", avx2));  // kernels the CPU cannot run
  EXPECT_FALSE(OpenBlasKernels::worth_it("", avx512));        // not OpenBLAS
  // Found in this process only where worth it, with the calls that hold its threads.
  const OpenBlasKernels& blas = OpenBlasKernels::loaded();
  if (!OpenBlasKernels::worth_it(openblas_core(), CpuFeatures::of_this_machine())) {
    EXPECT_EQ(blas.dsyrk, nullptr);
    EXPECT_EQ(blas.ssyrk, nullptr);
    EXPECT_EQ(blas.dgemm, nullptr);
    EXPECT_EQ(blas.sgemm, nullptr);
  } else {
    ASSERT_NE(blas.dsyrk, nullptr);
    ASSERT_NE(blas.ssyrk, nullptr);
    ASSERT_NE(blas.dgemm, nullptr);
    ASSERT_NE(blas.sgemm, nullptr);
    ASSERT_NE(blas.get_threads, nullptr);
    const int before = blas.get_threads();
    {
      const SerialOpenBlas serial(blas);
      EXPECT_EQ(blas.get_threads(), 1);
    }
    EXPECT_EQ(blas.get_threads(), before);
  }
}

TEST(BlasKernels, ThisProcessSeesItsOpenBlas) {
  // The tests link the same BLAS as the velum command: when it is OpenBLAS, its core is named.
  const std::string core = openblas_core();
  if (core.empty()) GTEST_SKIP() << "the BLAS loaded is not OpenBLAS";
  EXPECT_EQ(blas_coretype_to_request("set", core, CpuFeatures::of_this_machine()), "");
}

}  // namespace
}  // namespace velum
