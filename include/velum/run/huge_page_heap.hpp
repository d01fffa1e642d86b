// Transparent huge pages for the heap (docs/performance.md, "Huge pages for the heap"): glibc
// advises the kernel to back the heap with 2 MiB pages when the tunable glibc.malloc.hugetlb is
// 1, which is read only when the program starts. The `velum` launcher (app/launcher.cpp) sets
// it before it executes the program; the program started otherwise sets it and starts itself
// again (as it does for OpenBLAS's kernels, blas_kernels.hpp).
#pragma once

#include <string>
#include <string_view>

namespace velum::run {

/// The GLIBC_TUNABLES value that asks for a huge-page heap, given the current value (null when
/// unset), the kernel's THP mode (the contents of /sys/kernel/mm/transparent_hugepage/enabled)
/// and VELUM_HUGE_PAGES (null when unset); empty when nothing is to change: the user said 0,
/// THP is off ("[never]" or unknown), or the tunables already name hugetlb (set by the user,
/// or by this program before it started itself again).
std::string huge_page_tunables(const char* tunables, std::string_view thp_mode,
                               const char* velum_huge_pages);

/// Sets GLIBC_TUNABLES as huge_page_tunables says for this process (glibc 2.35 or later, where
/// the tunable exists); true when it changed it, and the program must start again to apply it.
/// With VELUM_HUGE_PAGES=0 it turns transparent huge pages off for the process instead
/// (PR_SET_THP_DISABLE: its own advice for the Cholesky's panels is then ignored too).
bool request_huge_page_heap();

/// Executes this program again with the same arguments and the environment as it now is;
/// returns only when that fails (the run goes on as it is).
void start_again(char** argv);

}  // namespace velum::run
