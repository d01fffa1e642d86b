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

/// The first n < kLanes<T> entries at p (the lanes past them zero), and stored back: one
/// masked vector where Eigen's packets are AVX-512's, a short copy elsewhere.
template <class T>
Packet<T> load_first(const T* p, int n) {
  alignas(64) T lanes[kLanes<T>] = {};
  for (int i = 0; i < n; ++i) lanes[i] = p[i];
  return Eigen::internal::ploadu<Packet<T>>(lanes);
}
template <class T>
void store_first(T* p, const Packet<T>& x, int n) {
  alignas(64) T lanes[kLanes<T>];
  Eigen::internal::pstoreu(lanes, x);
  for (int i = 0; i < n; ++i) p[i] = lanes[i];
}
#if defined(EIGEN_VECTORIZE_AVX512)
template <>
inline Packet<float> load_first<float>(const float* p, int n) {
  return _mm512_maskz_loadu_ps(static_cast<__mmask16>((1u << n) - 1), p);
}
template <>
inline void store_first<float>(float* p, const Packet<float>& x, int n) {
  _mm512_mask_storeu_ps(p, static_cast<__mmask16>((1u << n) - 1), x);
}
template <>
inline Packet<double> load_first<double>(const double* p, int n) {
  return _mm512_maskz_loadu_pd(static_cast<__mmask8>((1u << n) - 1), p);
}
template <>
inline void store_first<double>(double* p, const Packet<double>& x, int n) {
  _mm512_mask_storeu_pd(p, static_cast<__mmask8>((1u << n) - 1), x);
}
#endif

/// acc[c][p] = 0 for a block of C x P accumulators (kept in registers: the loops unrolled).
template <class T, int C, int P>
inline void clear(Packet<T> (&acc)[C][P]) {
#pragma GCC unroll 8
  for (int c = 0; c < C; ++c)
#pragma GCC unroll 8
    for (int p = 0; p < P; ++p) acc[c][p] = Eigen::internal::pset1<Packet<T>>(T(0));
}

}  // namespace velum::dense::packets
