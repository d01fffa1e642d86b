// What the supernodal Cholesky's factorisation (supernodal_cholesky.cpp) and its solves
// (supernodal_cholesky_solve.cpp) share: views of L's panels in either scalar, and the threads
// a split factorisation or solve runs on. The supernodal LU (supernodal_lu.cpp) takes the views.
#pragma once

#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>

namespace velum::supernodal {

template <class T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <class T>
using Panel = Eigen::Map<Matrix<T>, 0, Eigen::OuterStride<>>;
template <class T>
using ConstPanel = Eigen::Map<const Matrix<T>, 0, Eigen::OuterStride<>>;
template <class T>
using Segment = Eigen::Map<Eigen::Matrix<T, Eigen::Dynamic, 1>>;
template <class T>
using ConstSegment = Eigen::Map<const Eigen::Matrix<T, Eigen::Dynamic, 1>>;

// The threads that share a factorisation or a solve: two groups of subtrees, more help with
// the top.
inline int threads_for(std::size_t works) {
  return std::max(1, std::min(static_cast<int>(works), omp_get_max_threads()));
}

}  // namespace velum::supernodal
