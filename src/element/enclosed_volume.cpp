#include "velum/element/enclosed_volume.hpp"

namespace velum {
namespace {

// The shape's values, derivatives and weights at its Gauss points, computed once.
template <class Shape>
struct VolumePoints {
  std::array<typename Shape::Values, Shape::kPoints> N;
  std::array<typename Shape::Derivs, Shape::kPoints> dN;
  std::array<double, Shape::kPoints> w;
  static const VolumePoints& get() {
    static const VolumePoints table = [] {
      VolumePoints t;
      const auto rule = Shape::rule();
      for (int q = 0; q < Shape::kPoints; ++q) {
        Shape::eval(rule.xi[q][0], rule.xi[q][1], t.N[q], t.dN[q]);
        t.w[q] = rule.w[q] / 3.0;  // the ⅓ of the volume formula
      }
      return t;
    }();
    return table;
  }
};

// Point q's share of V and of its gradient, added to an (3 x nodes); y = x(q) − o and g, the
// point's position and tangent basis, are left for the Hessian.
// ∂[y, g1, g2]/∂x_N = N (g1 x g2) + N,1 (g2 x y) + N,2 (y x g1).
template <class Shape, class Nodes, class NodeForces>
inline double add_point_gradient(const Nodes& x, const Vec3& o, int q, NodeForces& an, Vec3& y,
                                 Eigen::Matrix<double, 3, 2>& g) {
  const auto& pts = VolumePoints<Shape>::get();
  const auto& N = pts.N[q];
  const auto& dN = pts.dN[q];
  const double w = pts.w[q];
  y = x * N - o;
  g = x * dN;
  const Vec3 n = g.col(0).cross(g.col(1));
  const Vec3 c1 = g.col(1).cross(y), c2 = y.cross(g.col(0));
  an.noalias() += w * (n * N.transpose() + c1 * dN.col(0).transpose() + c2 * dN.col(1).transpose());
  return w * y.dot(n);
}

}  // namespace

template <class Shape>
double EnclosedVolume<Shape>::volume(const Nodes& x, const Vec3& o) {
  const auto& pts = VolumePoints<Shape>::get();
  double V = 0;
  for (int q = 0; q < Shape::kPoints; ++q) {
    const Vec3 y = x * pts.N[q] - o;
    const Eigen::Matrix<double, 3, 2> g = x * pts.dN[q];
    V += pts.w[q] * y.dot(g.col(0).cross(g.col(1)));
  }
  return V;
}

template <class Shape>
double EnclosedVolume<Shape>::gradient(const Nodes& x, const Vec3& o, Vector& a) {
  Eigen::Matrix<double, 3, kN> an = Eigen::Matrix<double, 3, kN>::Zero();
  double V = 0;
  Vec3 y;
  Eigen::Matrix<double, 3, 2> g;
  for (int q = 0; q < Shape::kPoints; ++q) V += add_point_gradient<Shape>(x, o, q, an, y, g);
  a = Eigen::Map<const Vector>(an.data());
  return V;
}

template <class Shape>
double EnclosedVolume<Shape>::hessian(const Nodes& x, const Vec3& o, double scale, Vector& a,
                                      Matrix& H) {
  const auto& pts = VolumePoints<Shape>::get();
  Eigen::Matrix<double, 3, kN> an = Eigen::Matrix<double, 3, kN>::Zero();
  H.setZero();
  double V = 0;
  Vec3 y;
  Eigen::Matrix<double, 3, 2> g;
  for (int q = 0; q < Shape::kPoints; ++q) {
    V += add_point_gradient<Shape>(x, o, q, an, y, g);
    const auto& N = pts.N[q];
    const auto& dN = pts.dN[q];
    const double w = pts.w[q];
    // The triple product [y, g1, g2] is trilinear in x: its second derivative couples two
    // slots. Block (n, m) (rows x_n, columns x_m):
    //   N_n N,1m (−[g2]x) + N_n N,2m [g1]x + N,1n N_m [g2]x + N,1n N,2m (−[y]x)
    //   + N,2n N_m (−[g1]x) + N,2n N,1m [y]x
    const double s = scale * w;
    const Mat3 Y = s * cross_matrix(y), G1 = s * cross_matrix(g.col(0)),
               G2 = s * cross_matrix(g.col(1));
    for (int m = 0; m < kN; ++m)
      for (int k = 0; k < kN; ++k) {
        const double a12 = dN(k, 1) * dN(m, 0) - dN(k, 0) * dN(m, 1);  // y coefficient
        const double c2k = N[m] * dN(k, 0) - N[k] * dN(m, 0);          // g2 coefficient
        const double c1k = N[k] * dN(m, 1) - N[m] * dN(k, 1);          // g1 coefficient
        H.template block<3, 3>(3 * k, 3 * m) += a12 * Y + c2k * G2 + c1k * G1;
      }
  }
  a = Eigen::Map<const Vector>(an.data());
  return V;
}

template <class Shape>
double EnclosedVolume<Shape>::area(const Nodes& x, Vector* b) {
  // ∂|n|/∂x_N = N,1 (g2 x n̂) + N,2 (n̂ x g1), n = g1 x g2.
  const auto& pts = VolumePoints<Shape>::get();
  Eigen::Matrix<double, 3, kN> bn = Eigen::Matrix<double, 3, kN>::Zero();
  double A = 0;
  for (int q = 0; q < Shape::kPoints; ++q) {
    const Eigen::Matrix<double, 3, 2> g = x * pts.dN[q];
    const Vec3 n = g.col(0).cross(g.col(1));
    const double len = n.norm(), w = 3 * pts.w[q];  // the table's weights carry the volume's ⅓
    A += w * len;
    if (b && len > 0) {
      const Vec3 u = n / len;
      bn.noalias() += w * (g.col(1).cross(u) * pts.dN[q].col(0).transpose() +
                           u.cross(g.col(0)) * pts.dN[q].col(1).transpose());
    }
  }
  if (b) *b = Eigen::Map<const Vector>(bn.data());
  return A;
}

namespace {

template <class Shape>
class ShapeVolumeKernel final : public SurfaceVolumeKernel {
  using K = EnclosedVolume<Shape>;
  static constexpr int kN = Shape::kNodes;

 public:
  int nodes_per_element() const override { return kN; }

  double volume(std::span<const int> elements, std::span<const int> conn,
                const Eigen::Matrix<double, 3, Eigen::Dynamic>& x, const Vec3& o) const override {
    double V = 0;
    for (int e : elements) V += K::volume(nodes_of(e, conn, x), o);
    return V;
  }

  double area(std::span<const int> elements, std::span<const int> conn,
              const Eigen::Matrix<double, 3, Eigen::Dynamic>& x) const override {
    double A = 0;
    for (int e : elements) A += K::area(nodes_of(e, conn, x), nullptr);
    return A;
  }

  void area_gradient(std::span<const int> elements, std::span<const int> conn,
                     const Eigen::Matrix<double, 3, Eigen::Dynamic>& x, double* b) const override {
    typename K::Vector be;
    for (size_t k = 0; k < elements.size(); ++k) {
      K::area(nodes_of(elements[k], conn, x), &be);
      Eigen::Map<typename K::Vector>(b + k * K::kDofs) = be;
    }
  }

  void derivatives(std::span<const int> elements, std::span<const int> conn,
                   const Eigen::Matrix<double, 3, Eigen::Dynamic>& x, const Vec3& o, double scale,
                   double* a, double* H) const override {
    typename K::Vector ae;
    for (size_t k = 0; k < elements.size(); ++k) {
      const auto xe = nodes_of(elements[k], conn, x);
      if (H)
        K::hessian(xe, o, scale, ae,
                   *reinterpret_cast<typename K::Matrix*>(H + k * K::kDofs * K::kDofs));
      else
        K::gradient(xe, o, ae);
      Eigen::Map<typename K::Vector>(a + k * K::kDofs) = ae;
    }
  }

 private:
  static typename K::Nodes nodes_of(int e, std::span<const int> conn,
                                    const Eigen::Matrix<double, 3, Eigen::Dynamic>& x) {
    typename K::Nodes xe;
    for (int i = 0; i < kN; ++i) xe.col(i) = x.col(conn[static_cast<size_t>(e) * kN + i]);
    return xe;
  }
};

}  // namespace

std::unique_ptr<SurfaceVolumeKernel> make_surface_volume_kernel(std::string_view type) {
  const shape::ShapeInfo* info = shape::find(type);
  if (!info) return nullptr;
  return shape::with_shape(*info, []<class S>(S) -> std::unique_ptr<SurfaceVolumeKernel> {
    if constexpr (S::kDim == 2)
      return std::make_unique<ShapeVolumeKernel<S>>();
    else
      return nullptr;
  });
}

template struct EnclosedVolume<shape::Tri3>;
template struct EnclosedVolume<shape::Tri6>;
template struct EnclosedVolume<shape::Quad4>;
template struct EnclosedVolume<shape::Quad8>;
template struct EnclosedVolume<shape::Quad9>;

}  // namespace velum
