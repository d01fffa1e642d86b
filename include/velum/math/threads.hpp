// Loops and regions shared between OpenMP threads only when that is worth a fork: libgomp
// enters even a region of one thread (an `if` clause that is false, or --threads 1) through
// the kernel, a futex call each time, which was 4 % of the C9 canopy's CPU at 70 small
// regions per Newton iteration. Below the threshold, or on one thread, these run the body
// on the calling thread without entering libgomp at all.
#pragma once

#include <omp.h>

namespace velum {

/// True when a region of the given work should be shared: more than one thread available
/// and `worth` (the caller's size test) true.
inline bool share_between_threads(bool worth) {
  return worth && omp_get_max_threads() > 1;
}

/// body(i) for i in [0, n), statically scheduled over the threads when `worth` (and more
/// than one thread), else in order on the calling thread.
template <class Index, class Body>
void parallel_for(Index n, bool worth, const Body& body) {
  if (share_between_threads(worth)) {
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) body(i);
  } else {
    for (Index i = 0; i < n; ++i) body(i);
  }
}

/// body() run by every thread of a parallel region when `worth` (and more than one thread),
/// else once on the calling thread; a worksharing `#pragma omp for` inside body then binds
/// to that region, or runs whole on the calling thread.
template <class Body>
void parallel_region(bool worth, const Body& body) {
  if (share_between_threads(worth)) {
#pragma omp parallel
    body();
  } else {
    body();
  }
}

}  // namespace velum
