// Loops and regions shared between OpenMP threads only when that is worth a fork: libgomp
// enters even a region of one thread (an `if` clause that is false, or --threads 1) through
// the kernel, a futex call each time, which was 4 % of the C9 canopy's CPU at 70 small
// regions per Newton iteration. Below the threshold, or on one thread, these run the body
// on the calling thread without entering libgomp at all.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>

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

/// Entries per block of the vector loops below: fixed, so that the blocks (and the order of a
/// sum's partial sums) are the same whatever the thread count.
inline constexpr long kVectorBlock = 4096;

/// body(begin, end) over [0, n) in blocks of kVectorBlock entries, statically shared between
/// the threads when there are enough blocks to be worth a fork, else in order on the calling
/// thread. The per-step vector passes of an explicit run (a few hundred thousand entries).
template <class Body>
void parallel_ranges(long n, const Body& body) {
  const long blocks = (n + kVectorBlock - 1) / kVectorBlock;
  parallel_for(blocks, blocks >= 8,
               [&](long b) { body(b * kVectorBlock, std::min(n, (b + 1) * kVectorBlock)); });
}

/// The sum of body(begin, end) (a partial sum over [begin, end)) over [0, n): fixed blocks
/// (at most 256, at least kVectorBlock entries each) summed in block order, so the same bits
/// whatever the thread count.
template <class Body>
double parallel_sum(long n, const Body& body) {
  constexpr long kMaxBlocks = 256;
  const long block = std::max(kVectorBlock, (n + kMaxBlocks - 1) / kMaxBlocks);
  const long blocks = (n + block - 1) / block;
  std::array<double, kMaxBlocks> part{};
  parallel_for(blocks, blocks >= 8,
               [&](long b) { part[b] = body(b * block, std::min(n, (b + 1) * block)); });
  double sum = 0;
  for (long b = 0; b < blocks; ++b) sum += part[b];
  return sum;
}

}  // namespace velum
