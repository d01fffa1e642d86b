#include "velum/element/membrane.hpp"

#include "velum/material/plane_stress.hpp"

namespace velum {
namespace {

// Rows of a kernel's product operand: an element's dofs, rounded up to a multiple of 8 where
// they are no multiple of 4. Eigen vectorises a fixed-size product's columns with the widest
// packet that divides their length: 27 rows (a quad9) went two at a time, 9 and 18 (tri3,
// tri6) likewise; 12 and 24 (quad4, quad8) already go four at a time.
constexpr int padded_rows(int dofs) {
  return dofs % 4 == 0 ? dofs : (dofs + 7) / 8 * 8;
}

}  // namespace

template <class Shape>
const PointShapes<Shape>& PointShapes<Shape>::of(shape::Integration integration) {
  static const auto make = [](shape::Integration i) {
    PointShapes t;
    const auto rule = shape::rule_of<Shape>(i);
    for (int q = 0; q < Shape::kPoints; ++q) {
      Shape::eval(rule.xi[q][0], rule.xi[q][1], t.N[q], t.dN[q]);
      t.w[q] = rule.w[q];
    }
    return t;
  };
  static const PointShapes gauss = make(shape::Integration::kGauss);
  if constexpr (Shape::kNodalRule) {
    static const PointShapes nodal = make(shape::Integration::kNodal);
    if (integration == shape::Integration::kNodal) return nodal;
  }
  return gauss;
}

template <class Shape>
Eigen::Matrix<double, 3, 2> Membrane<Shape>::basis(const Nodes& X,
                                                   const std::array<double, 2>& xi) {
  typename Shape::Values N;
  typename Shape::Derivs dN;
  Shape::eval(xi[0], xi[1], N, dN);
  return X * dN;
}

template <class Shape>
Vec3 Membrane<Shape>::centre_normal(const Nodes& X) {
  const std::array<double, 2> c =
      Shape::kTriangle ? std::array<double, 2>{1.0 / 3, 1.0 / 3} : std::array<double, 2>{0.0, 0.0};
  const auto G = basis(X, c);
  return G.col(0).cross(G.col(1)).normalized();
}

template <class Shape>
double Membrane<Shape>::setup(const Nodes& X, const Mat3& Q, const SheetAxes& axes, double t0,
                              Points& pts, shape::Integration integration) {
  const auto rule = shape::rule_of<Shape>(integration);
  pts.shapes = &PointShapes<Shape>::of(integration);
  double min_jac = std::numeric_limits<double>::infinity();
  const Vec3 n_centre = centre_normal(X);
  for (int q = 0; q < kQ; ++q) {
    auto& p = pts[q];
    const Eigen::Matrix<double, 3, 2> G = X * pts.shapes->dN[q];
    const Mat2 Gcov = G.transpose() * G;
    const Vec3 normal = G.col(0).cross(G.col(1));
    // Signed area ratio: negative when the element folds over relative to its centre.
    const double jac = normal.norm() * (normal.dot(n_centre) >= 0 ? 1.0 : -1.0);
    min_jac = std::min(min_jac, jac);
    const Mat2 Ginv = Gcov.inverse();
    const Eigen::Matrix<double, 3, 2> Gcontra = G * Ginv;  // G^α = G^{αβ} G_β
    // Axes projected onto this point's tangent plane keep the fibres in the surface.
    const SheetAxes m = project_axes(axes, normal.normalized());
    for (int a = 0; a < 2; ++a) {
      const Vec3& ma = a == 0 ? m.m1 : m.m2;
      for (int al = 0; al < 2; ++al) p.T(a, al) = ma.dot(Gcontra.col(al));
    }
    p.t0dA = t0 * std::abs(jac) * rule.w[q];
    p.G = Vec3(Gcov(0, 0), Gcov(1, 1), Gcov(0, 1));
    p.D = transform_stiffness(Q, p.T) * p.t0dA;
  }
  return min_jac;
}

Mat3 sheet_strain_map(const Mat2& T) {
  // E_ab = T(a,α) T(b,β) γ_αβ, written for engineering shear on both sides.
  Mat3 A;
  A << T(0, 0) * T(0, 0), T(0, 1) * T(0, 1), T(0, 0) * T(0, 1),  //
      T(1, 0) * T(1, 0), T(1, 1) * T(1, 1), T(1, 0) * T(1, 1),   //
      2 * T(0, 0) * T(1, 0), 2 * T(0, 1) * T(1, 1), T(0, 0) * T(1, 1) + T(0, 1) * T(1, 0);
  return A;
}

template <class Shape>
void Membrane<Shape>::strain_stress(const Points& pts, int q, const Nodes& x, Vec3& e, Vec3& S,
                                    Eigen::Matrix<double, 3, 2>& g) {
  const auto& p = pts[q];
  g.noalias() = x * pts.shapes->dN[q];
  e << 0.5 * (g.col(0).squaredNorm() - p.G[0]), 0.5 * (g.col(1).squaredNorm() - p.G[1]),
      g.col(0).dot(g.col(1)) - p.G[2];
  S.noalias() = p.D * e / p.t0dA;
}

namespace {

// The internal forces rn (and, with kPressure, the pressure pr's forces fn) summed over the
// points: force() and force_and_pressure() are this one loop.
template <class M, bool kPressure, class Law>
[[gnu::always_inline]] inline void sum_forces(const typename M::Points& pts, const Law& law,
                                              const typename M::Nodes& x, double pr,
                                              Eigen::Matrix<double, 3, M::kN>& rn,
                                              Eigen::Matrix<double, 3, M::kN>& fn) {
  rn.setZero();
  if constexpr (kPressure) fn.setZero();
  for (int q = 0; q < M::kQ; ++q) {
    const auto& p = pts[q];
    const auto& dN = pts.shapes->dN[q];
    const Eigen::Matrix<double, 3, 2> g = x * dN;
    Vec3 S;  // weighted by t0 dA w
    law.stress(p, M::strain(p, g), S);
    Mat2 Sm;
    Sm << S[0], S[2], S[2], S[1];
    rn.noalias() += (g * Sm) * dN.transpose();
    if constexpr (kPressure)
      fn.noalias() +=
          (pr * pts.shapes->w[q]) * g.col(0).cross(g.col(1)) * pts.shapes->N[q].transpose();
  }
}

}  // namespace

template <class Shape>
// flatten: without it GCC calls strain() and the small products out of line in these member
// templates, and the linear kernels lose much of their speed.
template <class Law>
[[gnu::flatten]] void Membrane<Shape>::force(const Points& pts, const Law& law, const Nodes& x,
                                             Vector& r) {
  Eigen::Matrix<double, 3, kN> rn, unused;
  sum_forces<Membrane, false>(pts, law, x, 0.0, rn, unused);
  r = Eigen::Map<const Vector>(rn.data());
}

template <class Shape>
template <class Law>
[[gnu::flatten]] void Membrane<Shape>::force_and_pressure(const Points& pts, const Law& law,
                                                          const Nodes& x, double pr, Vector& r,
                                                          Vector& f) {
  Eigen::Matrix<double, 3, kN> rn, fn;
  sum_forces<Membrane, true>(pts, law, x, pr, rn, fn);
  r = Eigen::Map<const Vector>(rn.data());
  f = Eigen::Map<const Vector>(fn.data());
}

template <class Shape>
template <class Law>
[[gnu::flatten]] void Membrane<Shape>::force_tangent(const Points& pts, const Law& law,
                                                     const Nodes& x, Vector& r, Matrix& K) {
  Eigen::Matrix<double, 3, kN> rn = Eigen::Matrix<double, 3, kN>::Zero();
  NodeMatrix Kg = NodeMatrix::Zero();
  // K = Σ_q B_qᵀ D_q B_q as one product P Qᵀ, P = [B_0ᵀ D_0 ...], Q = [B_0ᵀ ...]: K's entries
  // stay in registers through the sum instead of being loaded and stored once a point.
  // P's rows padded with zeros to a multiple of 8 where they are no multiple of 4: the
  // product's columns are then whole packets (a quad9's 27 rows went two at a time; 1.8x
  // faster on AVX-512). The same sums, rounded differently (the C9 canopy's history by 9e-12).
  constexpr int kRows = padded_rows(kDofs);
  Eigen::Matrix<double, kRows, 3 * kQ> P;
  Eigen::Matrix<double, kDofs, 3 * kQ> Q;
  if constexpr (kRows > kDofs) P.template bottomRows<kRows - kDofs>().setZero();
  Mat3 scratch;
  for (int q = 0; q < kQ; ++q) {
    const auto& p = pts[q];
    const auto& dN = pts.shapes->dN[q];
    const Eigen::Matrix<double, 3, 2> g = x * dN;
    Vec3 S;
    const Mat3& D = law.tangent(p, strain(p, g), S, scratch);
    Mat2 Sm;
    Sm << S[0], S[2], S[2], S[1];
    rn.noalias() += (g * Sm) * dN.transpose();
    // Bᵀ: columns d(γ11), d(γ22), d(2γ12) with respect to x_N.
    auto Bt = Q.template middleCols<3>(3 * q);
    for (int n = 0; n < kN; ++n) {
      const double a = dN(n, 0), b = dN(n, 1);
      Bt.template block<3, 1>(3 * n, 0) = a * g.col(0);
      Bt.template block<3, 1>(3 * n, 1) = b * g.col(1);
      Bt.template block<3, 1>(3 * n, 2) = a * g.col(1) + b * g.col(0);
    }
    P.template block<kDofs, 3>(0, 3 * q).noalias() = Bt * D;
    Kg.noalias() += dN * Sm * dN.transpose();
  }
  if constexpr (kRows > kDofs) {
    const Eigen::Matrix<double, kRows, kDofs> Kp = P.lazyProduct(Q.transpose());
    K = Kp.template topRows<kDofs>();
  } else {
    K.noalias() = P.lazyProduct(Q.transpose());  // coefficient-based: no GEMM dispatch
  }
  for (int m = 0; m < kN; ++m)
    for (int n = 0; n < kN; ++n)
      K.template block<3, 3>(3 * m, 3 * n).diagonal().array() += Kg(m, n);
  r = Eigen::Map<const Vector>(rn.data());
}

template <class Shape>
template <class Law>
[[gnu::flatten]] double Membrane<Shape>::strain_energy(const Points& pts, const Law& law,
                                                       const Nodes& x) {
  double U = 0;
  for (int q = 0; q < kQ; ++q) {
    const auto& p = pts[q];
    const Eigen::Matrix<double, 3, 2> g = x * pts.shapes->dN[q];
    U += law.energy(p, strain(p, g));
  }
  return U;
}

template <class Shape>
bool Membrane<Shape>::keeps_orientation(const PointShapes<Shape>& shapes, const Nodes& from,
                                        const Nodes& to) {
  for (int q = 0; q < kQ; ++q) {
    const auto& dN = shapes.dN[q];
    const Eigen::Matrix<double, 3, 2> g0 = from * dN, g1 = to * dN;
    if (!(g0.col(0).cross(g0.col(1)).dot(g1.col(0).cross(g1.col(1))) > 0)) return false;
  }
  return true;
}

template <class Shape>
typename Membrane<Shape>::NodeMatrix Membrane<Shape>::tension_stiffness(const Points& pts) {
  NodeMatrix K = NodeMatrix::Zero();
  for (int q = 0; q < kQ; ++q) {
    const auto& p = pts[q];
    const auto& dN = pts.shapes->dN[q];
    Mat2 G;  // covariant metric; its inverse holds the contravariant G^{αβ}
    G << p.G[0], p.G[2], p.G[2], p.G[1];
    K.noalias() += dN * (p.t0dA * G.inverse()) * dN.transpose();
  }
  return K;
}

template <class Shape>
typename Membrane<Shape>::NodeMatrix Membrane<Shape>::mass(const Points& pts) {
  NodeMatrix M = NodeMatrix::Zero();
  for (int q = 0; q < kQ; ++q) {
    const auto& N = pts.shapes->N[q];
    M.noalias() += pts[q].t0dA * N * N.transpose();
  }
  return M;
}

template <class Shape>
[[gnu::flatten]] void Membrane<Shape>::pressure_force(const Points& pts, const Nodes& x, double pr,
                                                      Vector& f) {
  Eigen::Matrix<double, 3, kN> fn = Eigen::Matrix<double, 3, kN>::Zero();
  for (int q = 0; q < kQ; ++q) {
    const auto& dN = pts.shapes->dN[q];
    const Eigen::Matrix<double, 3, 2> g = x * dN;
    fn.noalias() +=
        (pr * pts.shapes->w[q]) * g.col(0).cross(g.col(1)) * pts.shapes->N[q].transpose();
  }
  f = Eigen::Map<const Vector>(fn.data());
}

template <class Shape>
[[gnu::flatten]] void Membrane<Shape>::pressure_force_tangent(const Points& pts, const Nodes& x,
                                                              double pr, Vector& f, Matrix& K) {
  Eigen::Matrix<double, 3, kN> fn = Eigen::Matrix<double, 3, kN>::Zero();
  // d(g1 x g2)/dx_n = H_n,2 [g1]x − H_n,1 [g2]x is a cross matrix, and so is K's block (m, n):
  // [v_mn]x with v_mn = Σ_q s_q H_m (H_n,2 g1 − H_n,1 g2). The vectors are summed, then expanded
  // (a third of the work of summing the 3 x 3 blocks), as one product: column q of A holds
  // s_q (H_n,2 g1 − H_n,1 g2) for every n, and V = A Hᵀ (H(m, q) = H_m at q) holds v_mn in
  // rows 3n..3n+2 of column m.
  // A's rows padded with zeros (whole packets, as in force_tangent).
  constexpr int kRows = padded_rows(kDofs);
  Eigen::Matrix<double, kRows, kQ> A;
  if constexpr (kRows > kDofs) A.template bottomRows<kRows - kDofs>().setZero();
  Eigen::Matrix<double, kQ, kN> H;
  for (int q = 0; q < kQ; ++q) {
    const auto& dN = pts.shapes->dN[q];
    const Eigen::Matrix<double, 3, 2> g = x * dN;
    const double s = pr * pts.shapes->w[q];
    fn.noalias() += s * g.col(0).cross(g.col(1)) * pts.shapes->N[q].transpose();
    for (int n = 0; n < kN; ++n)
      A.template block<3, 1>(3 * n, q) = s * (dN(n, 1) * g.col(0) - dN(n, 0) * g.col(1));
    H.row(q) = pts.shapes->N[q].transpose();
  }
  const Eigen::Matrix<double, kRows, kN> V = A.lazyProduct(H);
  for (int n = 0; n < kN; ++n)
    for (int m = 0; m < kN; ++m) {
      const double vx = V(3 * n, m), vy = V(3 * n + 1, m), vz = V(3 * n + 2, m);
      auto B = K.template block<3, 3>(3 * m, 3 * n);
      B(0, 0) = 0, B(1, 0) = vz, B(2, 0) = -vy;
      B(0, 1) = -vz, B(1, 1) = 0, B(2, 1) = vx;
      B(0, 2) = vy, B(1, 2) = -vx, B(2, 2) = 0;
    }
  f = Eigen::Map<const Vector>(fn.data());
}

template <class Shape>
void Membrane<Shape>::directed_pressure_force(const Points& pts, const Nodes& x, double pr,
                                              const Vec3& d, bool projected, Vector& f) {
  Eigen::Matrix<double, 1, kN> weights = Eigen::Matrix<double, 1, kN>::Zero();
  for (int q = 0; q < kQ; ++q) {
    const Eigen::Matrix<double, 3, 2> g = x * pts.shapes->dN[q];
    const Vec3 a = g.col(0).cross(g.col(1));
    const double phi = projected ? std::abs(a.dot(d)) : a.norm();
    weights.noalias() += (pts.shapes->w[q] * phi) * pts.shapes->N[q].transpose();
  }
  const Eigen::Matrix<double, 3, kN> fn = (pr * d) * weights;
  f = Eigen::Map<const Vector>(fn.data());
}

template <class Shape>
void Membrane<Shape>::directed_pressure_force_tangent(const Points& pts, const Nodes& x, double pr,
                                                      const Vec3& d, bool projected, Vector& f,
                                                      Matrix& K) {
  Eigen::Matrix<double, 1, kN> weights = Eigen::Matrix<double, 1, kN>::Zero();
  // dphi[n]: ∂φ/∂x_n summed with the weights H_m of each row m, kept per row below.
  K.setZero();
  const Vec3 pd = pr * d;
  for (int q = 0; q < kQ; ++q) {
    const auto& dN = pts.shapes->dN[q];
    const Eigen::Matrix<double, 3, 2> g = x * dN;
    const Vec3 a = g.col(0).cross(g.col(1));
    const double an = a.dot(d);
    const double phi = projected ? std::abs(an) : a.norm();
    const double w = pts.shapes->w[q];
    weights.noalias() += (w * phi) * pts.shapes->N[q].transpose();
    // φ = a·ŵ with ŵ = sign(a·d) d (projected) or a/|a|: ∂φ/∂x_n = H_n,1 (g2 x ŵ) + H_n,2 (ŵ x g1).
    if (phi == 0) continue;  // an edge-on point: no load, and φ has no derivative there
    const Vec3 wv = projected ? Vec3((an > 0 ? 1.0 : -1.0) * d) : Vec3(a / phi);
    const Vec3 c1 = g.col(1).cross(wv), c2 = wv.cross(g.col(0));
    for (int n = 0; n < kN; ++n) {
      const Vec3 dphi = dN(n, 0) * c1 + dN(n, 1) * c2;
      const Mat3 block = (w * pd) * dphi.transpose();
      for (int m = 0; m < kN; ++m)
        K.template block<3, 3>(3 * m, 3 * n) += pts.shapes->N[q][m] * block;
    }
  }
  const Eigen::Matrix<double, 3, kN> fn = pd * weights;
  f = Eigen::Map<const Vector>(fn.data());
}

template struct PointShapes<shape::Tri3>;
template struct PointShapes<shape::Tri6>;
template struct PointShapes<shape::Quad4>;
template struct PointShapes<shape::Quad8>;
template struct PointShapes<shape::Quad9>;
template struct Membrane<shape::Tri3>;
template struct Membrane<shape::Tri6>;
template struct Membrane<shape::Quad4>;
template struct Membrane<shape::Quad8>;
template struct Membrane<shape::Quad9>;

#define VELUM_MEMBRANE_LAW(Shape, Law)                                                            \
  template void Membrane<Shape>::force<Law>(const Points&, const Law&, const Nodes&, Vector&);    \
  template void Membrane<Shape>::force_and_pressure<Law>(const Points&, const Law&, const Nodes&, \
                                                         double, Vector&, Vector&);               \
  template void Membrane<Shape>::force_tangent<Law>(const Points&, const Law&, const Nodes&,      \
                                                    Vector&, Matrix&);                            \
  template double Membrane<Shape>::strain_energy<Law>(const Points&, const Law&, const Nodes&);
#define VELUM_MEMBRANE_LAWS(Shape)             \
  VELUM_MEMBRANE_LAW(Shape, ElasticPoints)     \
  VELUM_MEMBRANE_LAW(Shape, PrestressedPoints) \
  VELUM_MEMBRANE_LAW(Shape, LawPoints)         \
  VELUM_MEMBRANE_LAW(Shape, HistoryLawPoints)
VELUM_MEMBRANE_LAWS(shape::Tri3)
VELUM_MEMBRANE_LAWS(shape::Tri6)
VELUM_MEMBRANE_LAWS(shape::Quad4)
VELUM_MEMBRANE_LAWS(shape::Quad8)
VELUM_MEMBRANE_LAWS(shape::Quad9)
#undef VELUM_MEMBRANE_LAWS
#undef VELUM_MEMBRANE_LAW

}  // namespace velum
