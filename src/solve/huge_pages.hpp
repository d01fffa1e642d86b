// An array of doubles (or floats: the mixed-precision Cholesky's panels) on transparent huge
// pages where the kernel offers them (Linux, THP in "madvise" mode, as on Debian 12): the
// supernodal factorisations' panels, hundreds of MB written at scattered places, otherwise cost
// a page fault per 4 kB at their first touch and a TLB miss at most scattered writes. Zeroed when
// allocated; mapped directly (mmap), so that its pages go back to the system when released.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>

namespace velum {

template <class T>
class HugePageBuffer {
 public:
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;

  HugePageBuffer() = default;
  ~HugePageBuffer() { release(); }
  HugePageBuffer(const HugePageBuffer&) = delete;
  HugePageBuffer& operator=(const HugePageBuffer&) = delete;

  /// n zeros (the old contents released): fresh anonymous pages, touched first where the
  /// caller first writes them (where each page is first touched decides where the host keeps
  /// it: supernodal_cholesky.cpp's first_touch). On one thread as on two: the panels on 4 kB
  /// pages had cost one thread 3 to 7 % of a Hencky run since the heap itself moved to huge
  /// pages (src/run/huge_page_heap.cpp), in page faults and in the solves' TLB misses
  /// (docs/performance.md); before that, huge pages had made one-thread runs slower.
  void assign(std::size_t n) {
    release();
    size_ = n;
    if (n == 0) return;
    const std::size_t bytes = (n * sizeof(T) + kHugePage - 1) / kHugePage * kHugePage;
    // Mapped directly, aligned to a huge page by trimming a larger mapping: released, the pages
    // go back to the system (from malloc's heap they stayed: the mixed-precision Cholesky's
    // switch between float and double panels kept both in the process's memory).
    const std::size_t span = bytes + kHugePage;
    void* mapped = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    char* base = static_cast<char*>(mapped);
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(base);
    char* p = base + ((kHugePage - at % kHugePage) % kHugePage);
    if (p > base) munmap(base, static_cast<std::size_t>(p - base));
    if (base + span > p + bytes)
      munmap(p + bytes, static_cast<std::size_t>(base + span - (p + bytes)));
#ifdef MADV_HUGEPAGE
    madvise(p, bytes, MADV_HUGEPAGE);  // advice only: ignored where THP is off
#endif
    data_ = reinterpret_cast<T*>(p);
    bytes_ = bytes;
  }
  T* data() {
    return data_;
  }
  const T* data() const {
    return data_;
  }
  std::size_t size() const {
    return size_;
  }

 private:
  void release() {
    if (data_) munmap(data_, bytes_);
    data_ = nullptr;
    bytes_ = 0;
  }

  T* data_ = nullptr;
  std::size_t size_ = 0, bytes_ = 0;
};

}  // namespace velum
