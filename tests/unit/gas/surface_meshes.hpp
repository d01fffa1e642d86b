// Surface meshes for the enclosed-gas tests: parametric patches (u, v) -> R³ meshed with any
// membrane shape (the element nodes mapped from a grid of cells on the unit square or the
// unit triangle), coincident nodes merged. Element normals g1 x g2 follow ∂/∂u x ∂/∂v.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "velum/shape/shapes.hpp"

namespace velum::test {

using Patch = std::function<Vec3(double u, double v)>;

struct SurfaceMesh {
  std::vector<Vec3> nodes;
  std::vector<int> connectivity;
  std::map<std::tuple<long, long, long>, int> index;  // rounded coordinates -> node

  int node(const Vec3& x) {
    const auto key = std::make_tuple(std::lround(x.x() * 1e9), std::lround(x.y() * 1e9),
                                     std::lround(x.z() * 1e9));
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    nodes.push_back(x);
    index.emplace(key, static_cast<int>(nodes.size()) - 1);
    return static_cast<int>(nodes.size()) - 1;
  }
  Eigen::Matrix<double, 3, Eigen::Dynamic> X() const {
    Eigen::Matrix<double, 3, Eigen::Dynamic> x(3, nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) x.col(static_cast<Eigen::Index>(i)) = nodes[i];
    return x;
  }
};

/// Adds the n x n cells of `patch` on the unit square (triangle shapes: two per cell) or, with
/// `triangle_domain` (triangle shapes only), the n² cells of the unit triangle u + v <= 1.
template <class Shape>
void add_patch(SurfaceMesh& m, const Patch& patch, int n, bool triangle_domain = false) {
  const auto ref = Shape::nodes();
  auto add = [&](const Vec2& p0, const Vec2& p1, const Vec2& p2) {  // affine cell map
    for (const auto& xi : ref) {
      Vec2 uv;
      if constexpr (Shape::kTriangle)
        uv = p0 + xi[0] * (p1 - p0) + xi[1] * (p2 - p0);
      else  // p0: lower-left corner, p1: cell size in u and v
        uv = p0 + Vec2(0.5 * (xi[0] + 1) * p1.x(), 0.5 * (xi[1] + 1) * p1.y());
      m.connectivity.push_back(m.node(patch(uv.x(), uv.y())));
    }
  };
  const double h = 1.0 / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec2 a(i * h, j * h), b((i + 1) * h, j * h), c((i + 1) * h, (j + 1) * h),
          d(i * h, (j + 1) * h);
      if constexpr (Shape::kTriangle) {
        if (triangle_domain) {
          if (i + j < n) add(a, b, d);
          if (i + j < n - 1) add(b, c, d);
        } else {
          add(a, b, c);
          add(a, c, d);
        }
      } else {
        add(a, Vec2(h, h), Vec2());
      }
    }
}

}  // namespace velum::test
