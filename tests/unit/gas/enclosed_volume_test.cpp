// The enclosed-volume kernels (element/enclosed_volume): gradient and Hessian against central
// finite differences on distorted curved elements of every shape, and the volume of closed
// and symmetry-closed surfaces against exact values for every shape (each surface exactly in
// the shape's polynomial space, so the discrete volume is the exact one up to round-off).
#include <gtest/gtest.h>

#include "../support.hpp"
#include "surface_meshes.hpp"
#include "velum/element/enclosed_volume.hpp"

namespace velum {
namespace {

template <class Shape>
class EnclosedVolumeTest : public ::testing::Test {};
using Shapes = ::testing::Types<shape::Tri3, shape::Tri6, shape::Quad4, shape::Quad8, shape::Quad9>;
TYPED_TEST_SUITE(EnclosedVolumeTest, Shapes);

TYPED_TEST(EnclosedVolumeTest, GradientAndHessianMatchFiniteDifferences) {
  using S = TypeParam;
  using K = EnclosedVolume<S>;
  test::Random rnd(11);
  const auto X =
      test::distorted_element<S>(rnd, 1.0, 0.15, 0.2, rnd.rotation(0.7), rnd.vec3(-1, 1));
  const Vec3 o = rnd.vec3(-0.5, 0.5);
  typename K::Vector a;
  typename K::Matrix H;
  const double scale = 1.7;
  const double V = K::hessian(X, o, scale, a, H);
  EXPECT_NEAR(V, K::volume(X, o), 1e-14);
  typename K::Vector a2;
  EXPECT_NEAR(K::gradient(X, o, a2), V, 1e-14);
  EXPECT_LT((a2 - a).norm(), 1e-14 * a.norm());
  const auto afd = test::fd_gradient<typename K::Vector>(
      X, 1e-6, [&](const typename K::Nodes& x) { return K::volume(x, o); });
  EXPECT_LT((afd - a).cwiseAbs().maxCoeff(), 1e-8 * a.cwiseAbs().maxCoeff());
  const auto Hfd = test::fd_jacobian<typename K::Vector, typename K::Matrix>(
      X, 1e-6, [&](const typename K::Nodes& x, typename K::Vector& g) {
        K::gradient(x, o, g);
        g *= scale;
      });
  EXPECT_LT((Hfd - H).cwiseAbs().maxCoeff(), 1e-7 * H.cwiseAbs().maxCoeff());
  EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-13 * H.cwiseAbs().maxCoeff());
}

template <class S>
double mesh_volume(const test::SurfaceMesh& m, const Vec3& o) {
  const auto kernel = make_surface_volume_kernel(S::kName);
  const int ne = static_cast<int>(m.connectivity.size()) / S::kNodes;
  std::vector<int> all(ne);
  for (int e = 0; e < ne; ++e) all[e] = e;
  return kernel->volume(all, m.connectivity, m.X(), o);
}

// The closed box [0,2]x[0,1]x[0,1.5], interior nodes of each face moved within the face
// (non-affine elements, the same flat faces): volume 3 from any origin.
TYPED_TEST(EnclosedVolumeTest, ClosedBoxFromAnyOrigin) {
  using S = TypeParam;
  const Vec3 L(2.0, 1.0, 1.5);
  auto wobble = [](double u, double v) {  // zero on the patch boundary
    return 0.08 * std::sin(M_PI * u) * std::sin(M_PI * v) * (1 + u - v);
  };
  test::SurfaceMesh m;
  // Each face: (u, v) oriented so that ∂u x ∂v points outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // e_i x e_j = e_axis
      test::add_patch<S>(
          m,
          [&, axis, side, i, j](double u, double v) {
            double a = u + wobble(u, v), b = v - wobble(v, u);
            if (side == 0) std::swap(a, b);  // inward face: reversed parameters
            Vec3 x;
            x[axis] = side * L[axis];
            x[i] = a * L[i];
            x[j] = b * L[j];
            return x;
          },
          3);
    }
  for (const Vec3& o : {Vec3(0, 0, 0), Vec3(0.3, -2.0, 0.7), Vec3(5, 5, 5)})
    EXPECT_NEAR(mesh_volume<S>(m, o), 3.0, 1e-12) << "origin " << o.transpose();
}

// A sheet closed by the planes x = 0, y = 0, z = 0 through the origin: tri3 the plane
// x + y + z = 1 over the unit triangle (volume 1/6); the others the graph of
// z = c (1 − x)(1 − y)(1 + αx + βy) over the unit square (α = β = 0 for tri6 and quad4,
// whose spaces hold the bilinear term only), volume c (1/4 + α/12 + β/12). Closed by adding
// the walls x = 0 and y = 0 and the floor z = 0, the volume is the same from any origin.
TYPED_TEST(EnclosedVolumeTest, SymmetricAndClosedCurvedSurfaces) {
  using S = TypeParam;
  const bool quadratic_quad = S::kNodes >= 8;
  const double c = 0.8, al = quadratic_quad ? 0.5 : 0.0, be = quadratic_quad ? 0.3 : 0.0;
  auto f = [&](double x, double y) { return c * (1 - x) * (1 - y) * (1 + al * x + be * y); };
  test::SurfaceMesh sheet;
  double exact = 0;
  if constexpr (S::kNodes == 3) {
    test::add_patch<S>(
        sheet, [](double u, double v) { return Vec3(u, v, 1 - u - v); }, 4, true);
    exact = 1.0 / 6;
  } else {
    test::add_patch<S>(
        sheet, [&](double u, double v) { return Vec3(u, v, f(u, v)); }, 3);
    exact = c * (0.25 + al / 12 + be / 12);
  }
  EXPECT_NEAR(mesh_volume<S>(sheet, Vec3::Zero()), exact, 1e-13);

  test::SurfaceMesh closed = sheet;
  if constexpr (S::kNodes == 3) {
    // The three coordinate faces of the tetrahedron.
    test::add_patch<S>(
        closed, [](double u, double v) { return Vec3(0, v, u); }, 4, true);
    test::add_patch<S>(
        closed, [](double u, double v) { return Vec3(u, 0, v); }, 4, true);
    test::add_patch<S>(
        closed, [](double u, double v) { return Vec3(v, u, 0); }, 4, true);
  } else {
    // Wall x = 0: (0, s, t f(0, s)), normal −x; wall y = 0: (s, 0, t f(s, 0)), normal −y;
    // floor z = 0, normal −z.
    test::add_patch<S>(
        closed, [&](double u, double v) { return Vec3(0, v, u * f(0, v)); }, 3);
    test::add_patch<S>(
        closed, [&](double u, double v) { return Vec3(u, 0, v * f(u, 0)); }, 3);
    test::add_patch<S>(
        closed, [](double u, double v) { return Vec3(v, u, 0); }, 3);
  }
  for (const Vec3& o : {Vec3(0, 0, 0), Vec3(0.4, -1.0, 2.0)})
    EXPECT_NEAR(mesh_volume<S>(closed, o), exact, 1e-12) << "origin " << o.transpose();
}

}  // namespace
}  // namespace velum
