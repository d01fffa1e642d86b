// Helpers shared by the kernel unit tests (VERIFICATION.md section A): a seeded random source,
// distorted reference elements of every shape, the set of plane-stress laws exercised, and
// central finite differences of vector- and scalar-valued kernels.
#pragma once

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "velum/material/axes.hpp"
#include "velum/material/plane_stress.hpp"
#include "velum/shape/shapes.hpp"

namespace velum::test {

/// Deterministic random source (fixed seed per caller) with convenience draws.
class Random {
 public:
  explicit Random(unsigned seed) : gen_(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(gen_); }
  Vec3 vec3(double a, double b) { return {uniform(a, b), uniform(a, b), uniform(a, b)}; }
  Mat3 mat3(double a, double b) {
    Mat3 m;
    for (int i = 0; i < 9; ++i) m(i) = uniform(a, b);
    return m;
  }
  /// A rotation by `angle` (radians) about a random axis.
  Mat3 rotation(double angle) {
    return Eigen::AngleAxisd(angle, vec3(-1, 1).normalized()).toRotationMatrix();
  }

 private:
  std::mt19937_64 gen_;
};

/// Natural coordinates of the nodes of a surface shape, mapped to a reference square or
/// triangle of size h in the plane (quads: [-1,1]^2 -> [0,h]^2; triangles: unit -> h).
template <class Shape>
Vec2 natural_to_plane(const std::array<double, 2>& xi, double h) {
  if constexpr (Shape::kNodes == 3 || Shape::kNodes == 6) {
    return {h * xi[0], h * xi[1]};
  } else {
    return {0.5 * h * (xi[0] + 1), 0.5 * h * (xi[1] + 1)};
  }
}

/// A distorted element of size ~h: in-plane node perturbation `distort`·h, optional out-of-
/// plane bulge `bulge`·h (non-flat reference), then a rigid rotation R and a shift.
template <class Shape>
Eigen::Matrix<double, 3, Shape::kNodes> distorted_element(Random& rnd, double h, double distort,
                                                          double bulge, const Mat3& R,
                                                          const Vec3& shift) {
  Eigen::Matrix<double, 3, Shape::kNodes> X;
  const auto nodes = Shape::nodes();
  for (int n = 0; n < Shape::kNodes; ++n) {
    const Vec2 p = natural_to_plane<Shape>(nodes[n], h);
    const double px = p.x() + distort * h * rnd.uniform(-1, 1);
    const double py = p.y() + distort * h * rnd.uniform(-1, 1);
    const double pz = bulge * (px * px + 0.5 * py * py) / h;
    X.col(n) = R * Vec3(px, py, pz) + shift;
  }
  return X;
}

/// The laws every kernel test runs with (names printed with the measured errors).
inline std::vector<std::pair<std::string, PlaneStressLaw>> test_laws() {
  std::vector<std::pair<std::string, PlaneStressLaw>> laws;
  laws.emplace_back("isotropic", PlaneStressLaw::isotropic("iso", 1000.0, 0.3));
  laws.emplace_back("orthotropic",
                    PlaneStressLaw::orthotropic("ortho", 2000.0, 700.0, 0.35, 300.0, false));
  AnisotropicConstants c;
  c.E1 = 2000.0, c.E2 = 1000.0, c.nu12 = 0.3, c.G12 = 400.0, c.eta1 = 0.25, c.eta2 = -0.15;
  laws.emplace_back("anisotropic", PlaneStressLaw::anisotropic("aniso", c));
  laws.emplace_back("fibers", PlaneStressLaw::fibers("fib", {{1500.0, 75.0}, {900.0, 105.0}}));
  return laws;
}

/// Sheet axes at `deg` degrees from the local x axis of a sheet rotated by R (in-plane before
/// rotation), built through axes_from_points as a user would give them.
inline SheetAxes axes_at(double deg, const Mat3& R) {
  const double th = deg * std::numbers::pi / 180;
  const Vec3 P1 = R * Vec3(0.1, 0.2, 0.0);
  const Vec3 P2 = P1 + R * Vec3(std::cos(th), std::sin(th), 0.0);
  const Vec3 P3 = P1 + R * Vec3(-std::sin(th), std::cos(th), 0.0);
  return axes_from_points(P1, P2, P3);
}

/// Central finite-difference Jacobian of f: Nodes(3 x n) -> Vector(3n), node-major dofs.
template <class Vector, class Matrix, class Nodes, class F>
Matrix fd_jacobian(const Nodes& x, double h, const F& f) {
  Matrix J;
  Vector fp, fm;
  for (int j = 0; j < static_cast<int>(x.size()); ++j) {
    Nodes xp = x, xm = x;
    xp(j % 3, j / 3) += h;
    xm(j % 3, j / 3) -= h;
    f(xp, fp);
    f(xm, fm);
    J.col(j) = (fp - fm) / (2 * h);
  }
  return J;
}

/// Central finite-difference gradient of a scalar U(x), node-major.
template <class Vector, class Nodes, class U>
Vector fd_gradient(const Nodes& x, double h, const U& u) {
  Vector g;
  for (int j = 0; j < static_cast<int>(x.size()); ++j) {
    Nodes xp = x, xm = x;
    xp(j % 3, j / 3) += h;
    xm(j % 3, j / 3) -= h;
    g[j] = (u(xp) - u(xm)) / (2 * h);
  }
  return g;
}

/// Gauss-Legendre rule of n points on [-1, 1] (Newton on the Legendre recurrence), computed
/// here independently of the library's tabulated rules.
inline std::pair<std::vector<double>, std::vector<double>> gauss_legendre(int n) {
  std::vector<double> x(n), w(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
  return {x, w};
}

/// max|a - b| / max|b| (b the reference scale).
template <class A, class B>
double rel_max_error(const A& a, const B& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace velum::test
