// The CPU time (user + system) this process has used so far, in seconds: what the whole-run
// benchmarks report beside their wall time.
#pragma once

#include <sys/resource.h>

namespace velum::bench {

inline double process_cpu() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

}  // namespace velum::bench
