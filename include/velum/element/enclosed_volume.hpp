// The volume a membrane surface encloses with the symmetry planes through an origin o, for
// enclosed gas (docs/inflatables.md): V = ⅓ Σ_e ∫ (x − o)·(g1 x g2) dξ, exact for the
// element's polynomial surface (each shape's Gauss rule integrates the integrand exactly),
// with its gradient ∂V/∂x and its Hessian ∂²V/∂x² (symmetric). The planes through o add
// nothing to the integral ((x − o)·n = 0 on them). Kernels see node positions only and
// allocate nothing; coordinates global Cartesian, units the user's (volume: length³).
#pragma once

#include <memory>
#include <span>
#include <string_view>

#include "velum/shape/shape_info.hpp"

namespace velum {

template <class Shape>
struct EnclosedVolume {
  static constexpr int kN = Shape::kNodes;
  static constexpr int kDofs = 3 * kN;
  using Nodes = Eigen::Matrix<double, 3, kN>;
  using Vector = Eigen::Matrix<double, kDofs, 1>;  ///< node-major: (x1, y1, z1, x2, ...)
  using Matrix = Eigen::Matrix<double, kDofs, kDofs>;

  /// ⅓ ∫ (x − o)·(g1 x g2) dξ over the element.
  static double volume(const Nodes& x, const Vec3& o);
  /// The volume and its gradient a = ∂V/∂x.
  static double gradient(const Nodes& x, const Vec3& o, Vector& a);
  /// The volume, its gradient and `scale` times its Hessian ∂²V/∂x².
  static double hessian(const Nodes& x, const Vec3& o, double scale, Vector& a, Matrix& H);
  /// The current area ∫ |g1 x g2| dξ (the shape's Gauss rule) and its gradient ∂A/∂x
  /// (leakage through the fabric follows the stretched area).
  static double area(const Nodes& x, Vector* b);
};

/// The kernels of one shape behind a virtual interface (dispatch once per list of elements):
/// elements given by their node indices into x (3 x nodes), `connectivity` holding
/// nodes-per-element indices per element.
class SurfaceVolumeKernel {
 public:
  virtual ~SurfaceVolumeKernel() = default;
  virtual int nodes_per_element() const = 0;
  /// Sum of the element volumes of the listed elements.
  virtual double volume(std::span<const int> elements, std::span<const int> connectivity,
                        const Eigen::Matrix<double, 3, Eigen::Dynamic>& x, const Vec3& o) const = 0;
  /// Per listed element k: its gradient at a + k·dofs and (H non-null) `scale` times its
  /// Hessian at H + k·dofs² (column-major).
  virtual void derivatives(std::span<const int> elements, std::span<const int> connectivity,
                           const Eigen::Matrix<double, 3, Eigen::Dynamic>& x, const Vec3& o,
                           double scale, double* a, double* H) const = 0;
  /// Sum of the current areas of the listed elements.
  virtual double area(std::span<const int> elements, std::span<const int> connectivity,
                      const Eigen::Matrix<double, 3, Eigen::Dynamic>& x) const = 0;
  /// Per listed element k: its area's gradient at b + k·dofs.
  virtual void area_gradient(std::span<const int> elements, std::span<const int> connectivity,
                             const Eigen::Matrix<double, 3, Eigen::Dynamic>& x,
                             double* b) const = 0;
};

/// The kernel of a surface shape (shape_info.hpp) by its name; null for a line or an unknown name.
std::unique_ptr<SurfaceVolumeKernel> make_surface_volume_kernel(std::string_view type);

}  // namespace velum
