// An array of doubles on transparent huge pages where the kernel offers them (Linux, THP in
// "madvise" mode, as on Debian 12): the supernodal factorisations' panels, hundreds of MB
// written at scattered places, otherwise cost a page fault per 4 kB at their first touch and a
// TLB miss at most scattered writes. Zeroed when allocated (on the threads there are); a plain
// aligned array elsewhere.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <new>

namespace velum {

class HugePageArray {
 public:
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;

  HugePageArray() = default;
  ~HugePageArray() { std::free(data_); }
  HugePageArray(const HugePageArray&) = delete;
  HugePageArray& operator=(const HugePageArray&) = delete;

  /// n zeros (the old contents released).
  void assign(std::size_t n) {
    std::free(data_);
    data_ = nullptr;
    size_ = n;
    if (n == 0) return;
    const std::size_t bytes = (n * sizeof(double) + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, bytes);
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    madvise(p, bytes, MADV_HUGEPAGE);  // advice only: ignored where THP is off
#endif
    // The first touch is the costly part here (the kernel clears each page; in a virtual
    // machine the host backs it too: about 0.7 s for Hencky n = 130's panels on one thread):
    // shared among the threads there are.
    char* c = static_cast<char*>(p);
    const std::ptrdiff_t pages = static_cast<std::ptrdiff_t>(bytes / kHugePage);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < pages; ++k) std::memset(c + k * kHugePage, 0, kHugePage);
    data_ = static_cast<double*>(p);
  }
  double* data() {
    return data_;
  }
  const double* data() const {
    return data_;
  }
  std::size_t size() const {
    return size_;
  }

 private:
  double* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace velum
