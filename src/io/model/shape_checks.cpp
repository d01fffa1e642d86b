#include "shape_checks.hpp"

#include <fmt/format.h>

#include <cmath>

#include "velum/shape/shape_info.hpp"

namespace velum::io::model_file {
namespace {

/// Surface elements: the area ratio |G1 x G2| signed by the normal at the centre, at every
/// node, the centre and each Gauss point, must be positive.
template <class Shape>
ShapeProblem check_surfaces(std::span<const int> conn, const NodePositions& X,
                            std::span<const long> ids) {
  constexpr int kN = Shape::kNodes;
  typename Shape::Values N;
  typename Shape::Derivs dN;
  const double centre = Shape::kTriangle ? 1.0 / 3.0 : 0.0;
  const auto nodes = Shape::nodes();
  const auto rule = Shape::rule();
  const int ne = static_cast<int>(conn.size()) / kN;
  for (int e = 0; e < ne; ++e) {
    Eigen::Matrix<double, 3, kN> Xe;
    for (int i = 0; i < kN; ++i) {
      Xe.col(i) = X.col(conn[kN * e + i]);
      for (int j = 0; j < i; ++j)
        if (conn[kN * e + j] == conn[kN * e + i])
          return {e, fmt::format("repeats node {}", ids[conn[kN * e + i]])};
    }
    auto normal_at = [&](double r, double s) -> Vec3 {
      Shape::eval(r, s, N, dN);
      const Eigen::Matrix<double, 3, 2> G = Xe * dN;
      return G.col(0).cross(G.col(1));
    };
    const Vec3 nc = normal_at(centre, centre);
    const double scale = (Xe.rowwise().maxCoeff() - Xe.rowwise().minCoeff()).squaredNorm();
    if (!(nc.norm() > 1e-12 * scale)) return {e, "has no area at its centre (degenerate)"};
    const Vec3 unit = nc.normalized();
    for (int i = 0; i < kN; ++i)
      if (!(normal_at(nodes[i][0], nodes[i][1]).dot(unit) > 1e-12 * scale))
        return {e, fmt::format("crosses itself or folds over at node {}", ids[conn[kN * e + i]])};
    for (const auto& xi : rule.xi)
      if (!(normal_at(xi[0], xi[1]).dot(unit) > 1e-12 * scale))
        return {e, "crosses itself or folds over inside"};
  }
  return {};
}

/// Lines: distinct nodes, and dx/dξ along the chord at both ends and the middle.
template <class Shape>
ShapeProblem check_lines(std::span<const int> conn, const NodePositions& X,
                         std::span<const long> ids) {
  constexpr int kN = Shape::kNodes;
  typename Shape::Values N, dN;
  const int ne = static_cast<int>(conn.size()) / kN;
  for (int e = 0; e < ne; ++e) {
    Eigen::Matrix<double, 3, kN> Xe;
    for (int i = 0; i < kN; ++i) {
      Xe.col(i) = X.col(conn[kN * e + i]);
      for (int j = 0; j < i; ++j)
        if (conn[kN * e + j] == conn[kN * e + i])
          return {e, fmt::format("repeats node {}", ids[conn[kN * e + i]])};
    }
    const Vec3 chord = Xe.col(1) - Xe.col(0);
    if (!(chord.norm() > 0)) return {e, "has zero length"};
    for (double r : {-1.0, 0.0, 1.0}) {
      Shape::eval(r, N, dN);
      if (!((Xe * dN).dot(chord) > 1e-12 * chord.squaredNorm()))
        return {e, "folds back on itself (its middle node lies beyond an end)"};
    }
  }
  return {};
}

}  // namespace

ShapeProblem check_shapes(std::string_view type, std::span<const int> conn, const NodePositions& X,
                          std::span<const long> ids) {
  const shape::ShapeInfo* info = shape::find(type);
  if (!info) return {};
  return shape::with_shape(*info, [&]<class S>(S) {
    if constexpr (S::kDim == 2)
      return check_surfaces<S>(conn, X, ids);
    else
      return check_lines<S>(conn, X, ids);
  });
}

}  // namespace velum::io::model_file
