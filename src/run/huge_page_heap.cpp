#include "velum/run/huge_page_heap.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <unistd.h>

#if defined(__linux__)
#include <sys/prctl.h>
#endif

#if defined(__GLIBC__)
#include <gnu/libc-version.h>
#endif

namespace velum::run {

namespace {

bool refused(const char* velum_huge_pages) {
  return velum_huge_pages && std::strcmp(velum_huge_pages, "0") == 0;
}

}  // namespace

std::string huge_page_tunables(const char* tunables, std::string_view thp_mode,
                               const char* velum_huge_pages) {
  if (refused(velum_huge_pages)) return {};
  // "always [madvise] never": the bracketed word is the mode; madvise and always both honour
  // the advice glibc gives.
  if (thp_mode.find("[madvise]") == std::string_view::npos &&
      thp_mode.find("[always]") == std::string_view::npos)
    return {};
  const std::string current = tunables ? tunables : "";
  if (current.find("glibc.malloc.hugetlb") != std::string::npos) return {};
  return current.empty() ? "glibc.malloc.hugetlb=1" : current + ":glibc.malloc.hugetlb=1";
}

bool request_huge_page_heap() {
  // VELUM_HUGE_PAGES=0: no huge pages anywhere in the process, the panels' own advice
  // (huge_pages.hpp) included (the kernel then ignores MADV_HUGEPAGE; kept across exec).
  if (refused(std::getenv("VELUM_HUGE_PAGES"))) {
#if defined(__linux__)
    prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0);
#endif
    return false;
  }
#if defined(__GLIBC__)
  int major = 0, minor = 0;
  if (std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) != 2 ||
      major * 1000 + minor < 2035)
    return false;
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::stringstream mode;
  mode << in.rdbuf();
  const std::string want = huge_page_tunables(std::getenv("GLIBC_TUNABLES"), mode.str(),
                                              std::getenv("VELUM_HUGE_PAGES"));
  return !want.empty() && setenv("GLIBC_TUNABLES", want.c_str(), 1) == 0;
#else
  return false;
#endif
}

void start_again(char** argv) {
  if (argv && argv[0]) execv("/proc/self/exe", argv);
}

}  // namespace velum::run
