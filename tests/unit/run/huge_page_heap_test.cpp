// When the command line asks glibc for a huge-page heap (huge_page_heap.hpp): only where the
// kernel honours the advice, never against the user's own tunables or VELUM_HUGE_PAGES=0, and
// never twice (the program starts again with the value set, and must not loop).
#include "velum/run/huge_page_heap.hpp"

#include <gtest/gtest.h>
#include <sys/prctl.h>

#include <cstdlib>

namespace velum::run {
namespace {

TEST(HugePageHeap, AskedWhereTheKernelHonoursTheAdvice) {
  EXPECT_EQ(huge_page_tunables(nullptr, "always [madvise] never\n", nullptr),
            "glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables(nullptr, "[always] madvise never\n", nullptr),
            "glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables(nullptr, "always madvise [never]\n", nullptr), "");
  EXPECT_EQ(huge_page_tunables(nullptr, "", nullptr), "");  // no THP in this kernel
}

TEST(HugePageHeap, KeepsTheUsersTunablesAndChoice) {
  const char* thp = "always [madvise] never";
  EXPECT_EQ(huge_page_tunables("glibc.malloc.arena_max=2", thp, nullptr),
            "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
  EXPECT_EQ(huge_page_tunables("glibc.malloc.hugetlb=0", thp, nullptr), "");
  EXPECT_EQ(huge_page_tunables(nullptr, thp, "0"), "");
  EXPECT_EQ(huge_page_tunables(nullptr, thp, "1"), "glibc.malloc.hugetlb=1");
}

TEST(HugePageHeap, NotAskedAgainAfterTheRestart) {
  const std::string once = huge_page_tunables(nullptr, "[always] madvise never", nullptr);
  EXPECT_EQ(huge_page_tunables(once.c_str(), "[always] madvise never", nullptr), "");
}

// VELUM_HUGE_PAGES=0 means none at all: the process's transparent huge pages are turned off,
// so that the panels' MADV_HUGEPAGE is ignored too (in a child: the flag stays for a process's
// life).
TEST(HugePageHeap, NoneAtAllWhenTheUserSaysZero) {
  EXPECT_EXIT(
      {
        setenv("VELUM_HUGE_PAGES", "0", 1);
        const bool restart = request_huge_page_heap();
        std::exit(!restart && prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 1 ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        unsetenv("VELUM_HUGE_PAGES");
        request_huge_page_heap();
        std::exit(prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 0 ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace velum::run
