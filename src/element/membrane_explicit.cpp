#include "velum/element/membrane_explicit.hpp"

namespace velum {

template <class Shape>
const ExplicitShapes<Shape>& ExplicitShapes<Shape>::of(shape::Integration integration) {
  static const auto make = [](shape::Integration i) {
    const PointShapes<Shape>& ps = PointShapes<Shape>::of(i);
    ExplicitShapes t{};
    for (int q = 0; q < Shape::kPoints; ++q) {
      const int m = kQ == 1 ? 0 : q;  // a linear triangle's derivatives are one constant
      for (int n = 0; n < Shape::kNodes; ++n) {
        t.dN[0][n][m] = ps.dN[q](n, 0);
        t.dN[1][n][m] = ps.dN[q](n, 1);
        t.pw[n][m] += ps.w[q] * ps.N[q][n];
      }
    }
    return t;
  };
  static const ExplicitShapes gauss = make(shape::Integration::kGauss);
  if constexpr (Shape::kNodalRule) {
    static const ExplicitShapes nodal = make(shape::Integration::kNodal);
    if (integration == shape::Integration::kNodal) return nodal;
  }
  return gauss;
}

template <class Shape>
void MembraneExplicit<Shape>::record(const typename M::Points& pts, const Vec3& S0,
                                     ExplicitPoints<Shape>& out) {
  constexpr int Q = ExplicitPoints<Shape>::kQ;
  for (auto& row : out.row) row.fill(0.0);
  for (int q = 0; q < Shape::kPoints; ++q) {
    const auto& p = pts[q];
    const int m = Q == 1 ? 0 : q;  // merged: the sums of the weighted terms, one metric
    const Vec3 c = p.t0dA * (sheet_strain_map(p.T).transpose() * S0);
    const double d[6] = {p.D(0, 0),
                         p.D(1, 1),
                         p.D(2, 2),
                         0.5 * (p.D(0, 1) + p.D(1, 0)),
                         0.5 * (p.D(0, 2) + p.D(2, 0)),
                         0.5 * (p.D(1, 2) + p.D(2, 1))};
    for (int k = 0; k < 6; ++k) out.row[k][m] += d[k];
    for (int k = 0; k < 3; ++k) {
      out.row[6 + k][m] = p.G[k];
      out.row[9 + k][m] += c[k];
    }
  }
}

template <class Shape>
template <bool kPressure>
void MembraneExplicit<Shape>::force(const ExplicitShapes<Shape>& s,
                                    const ExplicitPoints<Shape>& pts, const Nodes& x, double p,
                                    Nodes& r, Nodes& f) {
  constexpr int Q = ExplicitPoints<Shape>::kQ, N = Shape::kNodes;
  const auto& R = pts.row;
  // The current basis g_a (a = 1, 2; components d) at every point.
  double g[2][3][Q];
  for (int a = 0; a < 2; ++a)
    for (int d = 0; d < 3; ++d)
      for (int q = 0; q < Q; ++q) {
        double v = x(d, 0) * s.dN[a][0][q];
        for (int n = 1; n < N; ++n) v += x(d, n) * s.dN[a][n][q];
        g[a][d][q] = v;
      }
  // Strain, weighted stress S = D γ + c, and g·S (h_a = g_b S^{ba}); the normal g1 x g2.
  double h[2][3][Q], nrm[3][Q];
  for (int q = 0; q < Q; ++q) {
    const double g00 = g[0][0][q], g01 = g[0][1][q], g02 = g[0][2][q];
    const double g10 = g[1][0][q], g11 = g[1][1][q], g12 = g[1][2][q];
    const double e0 = 0.5 * (g00 * g00 + g01 * g01 + g02 * g02 - R[6][q]);
    const double e1 = 0.5 * (g10 * g10 + g11 * g11 + g12 * g12 - R[7][q]);
    const double e2 = g00 * g10 + g01 * g11 + g02 * g12 - R[8][q];
    const double S0 = R[0][q] * e0 + R[3][q] * e1 + R[4][q] * e2 + R[9][q];
    const double S1 = R[3][q] * e0 + R[1][q] * e1 + R[5][q] * e2 + R[10][q];
    const double S2 = R[4][q] * e0 + R[5][q] * e1 + R[2][q] * e2 + R[11][q];
    for (int d = 0; d < 3; ++d) {
      h[0][d][q] = S0 * g[0][d][q] + S2 * g[1][d][q];
      h[1][d][q] = S2 * g[0][d][q] + S1 * g[1][d][q];
    }
    if constexpr (kPressure) {
      nrm[0][q] = g01 * g12 - g02 * g11;
      nrm[1][q] = g02 * g10 - g00 * g12;
      nrm[2][q] = g00 * g11 - g01 * g10;
    }
  }
  for (int n = 0; n < N; ++n)
    for (int d = 0; d < 3; ++d) {
      double v = 0, w = 0;
      for (int q = 0; q < Q; ++q) {
        v += h[0][d][q] * s.dN[0][n][q] + h[1][d][q] * s.dN[1][n][q];
        if constexpr (kPressure) w += nrm[d][q] * s.pw[n][q];
      }
      r(d, n) = v;
      if constexpr (kPressure) f(d, n) = p * w;
    }
}

#define VELUM_MEMBRANE_EXPLICIT(Shape)                                                            \
  template struct ExplicitShapes<Shape>;                                                          \
  template struct MembraneExplicit<Shape>;                                                        \
  template void MembraneExplicit<Shape>::force<true>(const ExplicitShapes<Shape>&,                \
                                                     const ExplicitPoints<Shape>&, const Nodes&,  \
                                                     double, Nodes&, Nodes&);                     \
  template void MembraneExplicit<Shape>::force<false>(const ExplicitShapes<Shape>&,               \
                                                      const ExplicitPoints<Shape>&, const Nodes&, \
                                                      double, Nodes&, Nodes&);
VELUM_MEMBRANE_EXPLICIT(shape::Tri3)
VELUM_MEMBRANE_EXPLICIT(shape::Tri6)
VELUM_MEMBRANE_EXPLICIT(shape::Quad4)
VELUM_MEMBRANE_EXPLICIT(shape::Quad8)
VELUM_MEMBRANE_EXPLICIT(shape::Quad9)
#undef VELUM_MEMBRANE_EXPLICIT

}  // namespace velum
