// The flattening's cells as least-squares residuals (src/analysis/flatten.cpp): the Green
// strain of a flat triangle or quadrilateral pulled onto its 3-D shape, weighted so that the
// residuals' squares sum to the cell's plane-stress energy, and their Gauss-Newton terms.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/SparseCore>

#include "velum/math/types.hpp"

namespace velum::flatten_cells {

// The Green strain of a flat map D (columns: the flat tangents of a parametrisation) pulled
// onto 3-D tangents of metric M, as residuals r with r^T r / 2 = w det(D) e^T C e / 2 (C = L
// L^T): w det(D) is the flat area the point stands for. NaN when D is folded.
template <class T>
Eigen::Matrix<T, 3, 1> metric_residual(const Eigen::Matrix<T, 2, 2>& D, const Mat2& M,
                                       const Mat3& Lt, double w) {
  const T det = D(0, 0) * D(1, 1) - D(0, 1) * D(1, 0);
  Eigen::Matrix<T, 2, 2> Di;
  Di << D(1, 1) / det, -D(0, 1) / det, -D(1, 0) / det, D(0, 0) / det;
  const Eigen::Matrix<T, 2, 2> C = Di.transpose() * M.cast<T>() * Di;
  Eigen::Matrix<T, 3, 1> e;
  e << (C(0, 0) - 1.0) / 2.0, (C(1, 1) - 1.0) / 2.0, C(0, 1);
  using std::sqrt;
  const T area = det * w;
  if (!(area > 0)) e.setConstant(T(std::numeric_limits<double>::quiet_NaN()));
  return sqrt(area > 0 ? area : T(1.0)) * (Lt.cast<T>() * e);
}

// The flat triangle P pulled onto the 3-D one (metric M = Q^T Q of its edges Q): the residual r
// with energy r^T r / 2 = A_flat e^T C e / 2 (L: C = L L^T). NaN when P is folded. Written out
// (as metric_residual with w = 1/2), as is the triangles' Gauss-Newton loop below: the
// compiler contracts them into the same round-off as the patterns written so far.
template <class T>
Eigen::Matrix<T, 3, 1> residual(const Eigen::Matrix<T, 6, 1>& P, const Mat2& M, const Mat3& Lt) {
  Eigen::Matrix<T, 2, 2> D;
  D << P[2] - P[0], P[4] - P[0], P[3] - P[1], P[5] - P[1];
  const T det = D(0, 0) * D(1, 1) - D(0, 1) * D(1, 0);
  Eigen::Matrix<T, 2, 2> Di;
  Di << D(1, 1) / det, -D(0, 1) / det, -D(1, 0) / det, D(0, 0) / det;
  const Eigen::Matrix<T, 2, 2> C = Di.transpose() * M.cast<T>() * Di;
  Eigen::Matrix<T, 3, 1> e;
  e << (C(0, 0) - 1.0) / 2.0, (C(1, 1) - 1.0) / 2.0, C(0, 1);
  using std::sqrt;
  const T area = det / 2.0;
  if (!(area > 0)) e.setConstant(T(std::numeric_limits<double>::quiet_NaN()));
  return sqrt(area > 0 ? area : T(1.0)) * (Lt.cast<T>() * e);
}

// The 2 x 2 Gauss point g of quad4 (xi, eta), corners in the order (-1, -1), (1, -1), (1, 1),
// (-1, 1), and the corners' shape function derivatives (d/dxi, d/deta) there.
inline Vec2 quad_point(int g) {
  const double a = 1 / std::sqrt(3.0);
  return Vec2(g == 1 || g == 2 ? a : -a, g >= 2 ? a : -a);
}
inline Eigen::Matrix<double, 4, 2> quad_gradients(int g) {
  const double xi = quad_point(g).x(), eta = quad_point(g).y();
  Eigen::Matrix<double, 4, 2> dN;
  dN << -(1 - eta), -(1 - xi), 1 - eta, -(1 + xi), 1 + eta, 1 + xi, -(1 + eta), 1 - xi;
  return dN / 4;
}

// The flat quadrilateral P (corners in the element's order) pulled onto the 3-D bilinear one
// as a quad4 element measures strain: at each Gauss point g the 3-D tangents' metric M[g]
// against the flat tangents, weighted by the flat area element (the 2 x 2 rule's weights 1).
// The flat tangents are written out from the edges: GCC 12.2 at -O3 -march=native (AVX-512)
// miscompiled the sum over the corners' shape function derivatives here into wrong tangents.
template <class T>
Eigen::Matrix<T, 12, 1> quad_residual(const Eigen::Matrix<T, 8, 1>& P, const std::array<Mat2, 4>& M,
                                      const Mat3& Lt) {
  Eigen::Matrix<T, 12, 1> r;
  for (int g = 0; g < 4; ++g) {
    const double xi = quad_point(g).x(), eta = quad_point(g).y();
    Eigen::Matrix<T, 2, 2> D;
    for (int i = 0; i < 2; ++i) {
      D(i, 0) = ((P[2 + i] - P[i]) * (1 - eta) + (P[4 + i] - P[6 + i]) * (1 + eta)) / 4.0;
      D(i, 1) = ((P[6 + i] - P[i]) * (1 - xi) + (P[4 + i] - P[2 + i]) * (1 + xi)) / 4.0;
    }
    r.template segment<3>(3 * g) = metric_residual<T>(D, M[g], Lt, 1.0);
  }
  return r;
}

// Adds a cell's residuals r (forward derivatives over its nodes' flat coordinates) to the
// Gauss-Newton system of the panel: g += J^T r and, with H, the entries of J^T J.
template <class R, size_t K>
void add_cell(const R& r, const std::array<int, K>& nodes, VecX& g,
              std::vector<Eigen::Triplet<double>>* H) {
  constexpr int n = 2 * static_cast<int>(K);
  Eigen::Matrix<double, R::RowsAtCompileTime, n> J;
  Eigen::Matrix<double, R::RowsAtCompileTime, 1> rv;
  for (int a = 0; a < R::RowsAtCompileTime; ++a)
    J.row(a) = r[a].derivatives().transpose(), rv[a] = r[a].value();
  const Eigen::Matrix<double, n, 1> Jr = J.transpose() * rv;
  const Eigen::Matrix<double, n, n> JJ = J.transpose() * J;
  for (int a = 0; a < n; ++a) {
    const int ia = 2 * nodes[a / 2] + a % 2;
    g[ia] += Jr[a];
    if (H)
      for (int b = 0; b < n; ++b) H->emplace_back(ia, 2 * nodes[b / 2] + b % 2, JJ(a, b));
  }
}

}  // namespace velum::flatten_cells
