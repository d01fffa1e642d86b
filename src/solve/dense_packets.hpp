// Eigen's SIMD packets as the dense kernels use them (dense_kernels.cpp, dense_products.cpp):
// the packet type of a scalar, its lanes, unaligned loads and stores, and clearing a block of
// accumulators.
#pragma once

#include <Eigen/Core>

// Eigen's packet types carry alignment attributes that a template argument drops (harmless:
// the packets are loaded and stored unaligned). Set for the files that include this one.
#pragma GCC diagnostic ignored "-Wignored-attributes"

namespace velum::dense::packets {

template <class T>
using Packet = typename Eigen::internal::packet_traits<T>::type;
template <class T>
constexpr int kLanes = Eigen::internal::unpacket_traits<Packet<T>>::size;

template <class T>
Packet<T> load(const T* p) {
  return Eigen::internal::ploadu<Packet<T>>(p);
}

template <class T>
void store(T* p, const Packet<T>& x) {
  Eigen::internal::pstoreu(p, x);
}

/// acc[c][p] = 0 for a block of C x P accumulators (kept in registers: the loops unrolled).
template <class T, int C, int P>
inline void clear(Packet<T> (&acc)[C][P]) {
#pragma GCC unroll 8
  for (int c = 0; c < C; ++c)
#pragma GCC unroll 8
    for (int p = 0; p < P; ++p) acc[c][p] = Eigen::internal::pset1<Packet<T>>(T(0));
}

}  // namespace velum::dense::packets
