// The `velum` command: sets what must be in place before the program's libraries load, then
// executes the program itself, velum-engine beside it, with the same arguments (the process
// stays the same: signals sent to it reach the run).
//
// glibc reads its tunables (glibc.malloc.hugetlb: a huge-page heap, huge_page_heap.hpp) once,
// when the dynamic loader starts the program. The program used to set the tunable and execute
// itself again, which loaded its thirty libraries twice: about 17 ms of CPU each time (most of
// it OpenBLAS's 12,000 symbol bindings), 2.5 % of a Hencky n = 64 run. This launcher loads
// libc and libstdc++ only. Started directly, velum-engine still sets the tunable and starts
// itself again, as before.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <unistd.h>

#include "velum/run/huge_page_heap.hpp"

int main(int, char** argv) {
  velum::run::request_huge_page_heap();  // the environment the engine then starts with
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  std::string engine = "velum-engine";
  if (n > 0) {
    self[n] = '\0';
    std::string here(self);
    engine = here.substr(0, here.rfind('/') + 1) + engine;
  }
  execv(engine.c_str(), argv);
  std::fprintf(stderr,
               "error: velum cannot start %s: %s (it is installed beside the velum command: "
               "build or install Velum again)\n",
               engine.c_str(), std::strerror(errno));
  return 127;
}
