#include "velum/analysis/flatten.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <unsupported/Eigen/AutoDiff>

#include "flatten_cells.hpp"

#include "velum/math/sparse.hpp"

namespace velum {
namespace {

using flatten_cells::add_cell;
using flatten_cells::quad_gradients;
using flatten_cells::quad_residual;
using flatten_cells::residual;

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec8 = Eigen::Matrix<double, 8, 1>;
using Ad = Eigen::AutoDiffScalar<Vec6>;
using Ad8 = Eigen::AutoDiffScalar<Vec8>;

// A 3-D triangle in its own plane: q0 at the origin, q1 on the first axis.
std::array<Vec2, 3> local_triangle(const NodePositions& x, const std::array<int, 3>& t) {
  const Vec3 e1 = x.col(t[1]) - x.col(t[0]), e2 = x.col(t[2]) - x.col(t[0]);
  const Vec3 ex = e1.normalized();
  const Vec3 ey = e1.cross(e2).cross(e1).normalized();
  return {Vec2::Zero(), Vec2(e1.norm(), 0), Vec2(e2.dot(ex), e2.dot(ey))};
}

Mat3 plane_stress_factor(double nu) {
  Mat3 C;
  C << 1, nu, 0, nu, 1, 0, 0, 0, (1 - nu) / 2;
  C /= 1 - nu * nu;
  return Mat3(C.llt().matrixL().transpose());
}

struct Triangles {
  std::vector<Mat2> metric;  // Q^T Q per triangle
  std::vector<double> area;
  std::vector<std::array<Mat2, 4>> quad_metric;  // per quadrilateral, at its Gauss points
  std::vector<size_t> quad_triangle;             // per quadrilateral, its first triangle
};

Triangles metrics(const NodePositions& x, const FlatPanel& p) {
  Triangles t;
  for (const auto& tri : p.triangles) {
    const std::array<int, 3> g{p.nodes[tri[0]], p.nodes[tri[1]], p.nodes[tri[2]]};
    const auto q = local_triangle(x, g);
    Mat2 Q;
    Q << q[1] - q[0], q[2] - q[0];
    t.metric.push_back(Q.transpose() * Q);
    t.area.push_back(Q.determinant() / 2);
  }
  for (const auto& quad : p.quads) {
    Eigen::Matrix<double, 3, 4> X;
    for (int k = 0; k < 4; ++k) X.col(k) = x.col(p.nodes[quad[k]]);
    std::array<Mat2, 4>& M = t.quad_metric.emplace_back();
    for (int g = 0; g < 4; ++g) {
      const Eigen::Matrix<double, 3, 2> G = X * quad_gradients(g);
      M[g] = G.transpose() * G;
    }
  }
  t.quad_triangle.assign(p.quads.size(), 0);
  for (size_t i = p.quad_of.size(); i-- > 0;)
    if (p.quad_of[i] >= 0) t.quad_triangle[static_cast<size_t>(p.quad_of[i])] = i;
  return t;
}

template <int K>
Eigen::Matrix<double, 2 * K, 1> corners(const std::vector<Vec2>& uv, const std::array<int, K>& t) {
  Eigen::Matrix<double, 2 * K, 1> P;
  for (int k = 0; k < K; ++k) P.template segment<2>(2 * k) = uv[t[k]];
  return P;
}

bool in_quad(const FlatPanel& p, size_t i) {
  return i < p.quad_of.size() && p.quad_of[i] >= 0;
}

// Visits every cell's residuals at uv: the triangles that are no quadrilateral's, then the
// quadrilaterals, as visit(residuals, local nodes), with the scalar type T (double, or a
// forward derivative over the cell's coordinates).
template <bool kDerivatives, class Visit>
void for_each_cell(const FlatPanel& p, const Triangles& m, const std::vector<Mat3>& Lt,
                   const std::vector<Vec2>& uv, Visit&& visit) {
  for (size_t i = 0; i < p.triangles.size(); ++i) {
    if (in_quad(p, i)) continue;
    const auto& t = p.triangles[i];
    const Vec6 pv = corners<3>(uv, t);
    if constexpr (kDerivatives) {
      Eigen::Matrix<Ad, 6, 1> P;
      for (int k = 0; k < 6; ++k) P[k] = Ad(pv[k], 6, k);
      visit(residual<Ad>(P, m.metric[i], Lt[i]), t);
    } else {
      visit(residual<double>(pv, m.metric[i], Lt[i]), t);
    }
  }
  for (size_t q = 0; q < p.quads.size(); ++q) {
    const auto& t = p.quads[q];
    const Vec8 pv = corners<4>(uv, t);
    const Mat3& L = Lt[m.quad_triangle[q]];
    if constexpr (kDerivatives) {
      Eigen::Matrix<Ad8, 8, 1> P;
      for (int k = 0; k < 8; ++k) P[k] = Ad8(pv[k], 8, k);
      visit(quad_residual<Ad8>(P, m.quad_metric[q], L), t);
    } else {
      visit(quad_residual<double>(pv, m.quad_metric[q], L), t);
    }
  }
}

double energy_of(const FlatPanel& p, const Triangles& m, const std::vector<Mat3>& Lt,
                 const std::vector<Vec2>& uv) {
  double E = 0;
  for_each_cell<false>(p, m, Lt, uv, [&](const auto& r, const auto&) { E += r.squaredNorm() / 2; });
  return std::isfinite(E) ? E : std::numeric_limits<double>::infinity();
}

// The 3-D direction a on triangle i carried into the flat one: d = F^+ a with F = G D^-1 the
// flat-to-3-D map; zero when it does not map (a direction across the triangle).
Vec2 flat_direction(const NodePositions& x, const FlatPanel& p, size_t i, const Vec3& a) {
  const auto& t = p.triangles[i];
  Eigen::Matrix<double, 3, 2> G;
  G << x.col(p.nodes[t[1]]) - x.col(p.nodes[t[0]]), x.col(p.nodes[t[2]]) - x.col(p.nodes[t[0]]);
  Mat2 D;
  D << p.uv[t[1]] - p.uv[t[0]], p.uv[t[2]] - p.uv[t[0]];
  const Eigen::Matrix<double, 3, 2> F = G * D.inverse();
  const Vec2 d = (F.transpose() * F).ldlt().solve(F.transpose() * a);
  return d.allFinite() && d.norm() > 0 ? Vec2(d.normalized()) : Vec2::Zero();
}

// Per triangle, the factor L^T of the energy's C = L L^T in the flat (u, v) frame: the law's
// stiffness in its sheet axes turned to the flat warp direction of the triangle (e_sheet =
// R e_flat, C_flat = R^T C R), or the isotropic one.
std::vector<Mat3> energy_factors(const NodePositions& x, const FlatPanel& p, const PanelMesh& mesh,
                                 const FlattenSettings& settings, bool& turned) {
  const Mat3 iso = plane_stress_factor(settings.nu);
  std::vector<Mat3> Lt(p.triangles.size(), iso);
  const double scale = settings.stiffness.cwiseAbs().maxCoeff();
  if (!(scale > 0) || mesh.warp.size() != mesh.triangles.size()) return Lt;
  const Mat3 C = settings.stiffness / scale;
  for (size_t i = 0; i < p.triangles.size(); ++i) {
    const Vec2 d = flat_direction(x, p, i, mesh.warp[i]);
    if (d.norm() == 0) continue;
    const double c = d.x(), s = d.y();
    Mat3 R;
    R << c * c, s * s, c * s, s * s, c * c, -c * s, -2 * c * s, 2 * c * s, c * c - s * s;
    Eigen::LLT<Mat3> llt(R.transpose() * C * R);
    if (llt.info() == Eigen::Success) Lt[i] = llt.matrixL().transpose(), turned = true;
  }
  return Lt;
}

// Least-squares conformal map (Cauchy-Riemann residuals per triangle, two boundary nodes
// pinned at their 3-D distance apart); returns the pinned nodes (the first at the origin, the
// second on the u axis).
std::pair<int, int> conformal_map(const NodePositions& x, FlatPanel& p) {
  const int n = static_cast<int>(p.nodes.size());
  // Pins: two outline nodes far apart.
  auto farthest = [&](int from) {
    int best = p.outline.front();
    double d = -1;
    for (int k : p.outline)
      if (const double dk = (x.col(p.nodes[k]) - x.col(p.nodes[from])).norm(); dk > d)
        d = dk, best = k;
    return best;
  };
  const int a = farthest(p.outline.front()), b = farthest(a);
  const double chord = (x.col(p.nodes[a]) - x.col(p.nodes[b])).norm();
  std::vector<int> col(2 * static_cast<size_t>(n), -1);
  int free = 0;
  for (int k = 0; k < n; ++k)
    if (k != a && k != b) col[2 * k] = free++, col[2 * k + 1] = free++;
  const VecX pinned = (VecX(4) << 0, 0, chord, 0).finished();
  auto pin_index = [&](int k, int c) { return (k == a ? 0 : 2) + c; };
  std::vector<Eigen::Triplet<double>> J;
  VecX rhs = VecX::Zero(2 * static_cast<long>(p.triangles.size()));
  for (size_t i = 0; i < p.triangles.size(); ++i) {
    const auto& t = p.triangles[i];
    const auto q = local_triangle(x, {p.nodes[t[0]], p.nodes[t[1]], p.nodes[t[2]]});
    const double A =
        ((q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x()) / 2;
    const double w = std::sqrt(A) / (2 * A);
    for (int k = 0; k < 3; ++k) {
      const Vec2 e = q[(k + 2) % 3] - q[(k + 1) % 3];
      const Vec2 g(-e.y(), e.x());  // gradient of the hat function times 2A
      // rows: grad v - perp(grad u) = (v_x + u_y, v_y - u_x)
      const double coef[2][2] = {{g.y(), g.x()}, {-g.x(), g.y()}};  // [row][u or v]
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
          const double v = w * coef[r][c];
          const int j = col[2 * t[k] + c];
          const long row = 2 * static_cast<long>(i) + r;
          if (j >= 0)
            J.emplace_back(static_cast<int>(row), j, v);
          else
            rhs[row] -= v * pinned[pin_index(t[k], c)];
        }
    }
  }
  SparseMatrix Js(static_cast<int>(rhs.size()), free);
  Js.setFromTriplets(J.begin(), J.end());
  const SparseMatrix N = Js.transpose() * Js;
  Eigen::SimplicialLDLT<SparseMatrix> solve(N);
  if (solve.info() != Eigen::Success) throw std::runtime_error("pattern: the conformal map failed");
  const VecX z = solve.solve(VecX(Js.transpose() * rhs));
  p.uv.assign(static_cast<size_t>(n), Vec2::Zero());
  for (int k = 0; k < n; ++k)
    p.uv[k] = k == a   ? Vec2(0, 0)
              : k == b ? Vec2(chord, 0)
                       : Vec2(z[col[2 * k]], z[col[2 * k + 1]]);
  return {a, b};
}

// The panel's outline from its boundary edges (edges of one triangle), in their direction.
std::vector<int> outline_of(const std::vector<std::array<int, 3>>& tris) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const int i = t[k], j = t[(k + 1) % 3];
      ++count[{std::min(i, j), std::max(i, j)}];
    }
  std::map<int, int> next;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      const int i = t[k], j = t[(k + 1) % 3];
      if (count[{std::min(i, j), std::max(i, j)}] == 1) next[i] = j;
    }
  std::vector<int> loop;
  if (next.empty()) return loop;
  const int first = next.begin()->first;
  int at = first;
  do {
    loop.push_back(at);
    at = next.at(at);
  } while (at != first && loop.size() <= next.size());
  return loop;
}

}  // namespace

std::string disc_problem(const PanelMesh& mesh, int num_nodes) {
  if (mesh.triangles.empty()) return "it has no surface elements";
  std::map<std::pair<int, int>, int> edges;
  std::vector<int> parent(static_cast<size_t>(num_nodes));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<char> used(static_cast<size_t>(num_nodes), 0);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int i = t[k], j = t[(k + 1) % 3];
      used[i] = 1;
      ++edges[{std::min(i, j), std::max(i, j)}];
      parent[root(i)] = root(j);
    }
  long V = 0, pieces = 0;
  for (int i = 0; i < num_nodes; ++i)
    if (used[i]) ++V, pieces += root(i) == i;
  for (const auto& [e, c] : edges)
    if (c > 2) return fmt::format("an edge is shared by {} of its elements (not a surface)", c);
  if (pieces > 1) return fmt::format("it is {} separate pieces, not one", pieces);
  std::vector<int> boundary(static_cast<size_t>(num_nodes), 0);
  for (const auto& [e, c] : edges)
    if (c == 1) ++boundary[e.first], ++boundary[e.second];
  for (int i = 0; i < num_nodes; ++i)
    if (boundary[i] != 0 && boundary[i] != 2)
      return fmt::format("its elements touch at node {} only (index; not a disc)", i);
  const long chi = V - static_cast<long>(edges.size()) + static_cast<long>(mesh.triangles.size());
  if (chi != 1)
    return fmt::format(
        "it is not a disc (Euler characteristic {}, a disc has 1): it has {} holes or is closed; "
        "cut it into discs along seams",
        chi, chi < 1 ? std::to_string(1 - chi) : std::string("no boundary or no"));
  return {};
}

double flattening_energy(const NodePositions& x, const FlatPanel& panel, double nu,
                         VecX* gradient) {
  const Triangles m = metrics(x, panel);
  const std::vector<Mat3> Lt(panel.triangles.size(), plane_stress_factor(nu));
  double E = 0;
  VecX g = VecX::Zero(2 * static_cast<long>(panel.uv.size()));
  for_each_cell<true>(panel, m, Lt, panel.uv, [&](const auto& r, const auto& nodes) {
    for (int a = 0; a < r.size(); ++a) E += r[a].value() * r[a].value() / 2;
    if (gradient) add_cell(r, nodes, g, nullptr);
  });
  if (gradient) *gradient = g;
  return E;
}

FlatPanel flatten_panel(const NodePositions& x, const PanelMesh& mesh,
                        const FlattenSettings& settings) {
  if (std::string why = disc_problem(mesh, static_cast<int>(x.cols())); !why.empty())
    throw std::invalid_argument(why);
  FlatPanel p;
  std::map<int, int> local;
  for (const auto& t : mesh.triangles) {
    std::array<int, 3> l{};
    for (int k = 0; k < 3; ++k) {
      auto [it, added] = local.emplace(t[k], static_cast<int>(p.nodes.size()));
      if (added) p.nodes.push_back(t[k]);
      l[k] = it->second;
    }
    p.triangles.push_back(l);
  }
  for (const auto& q : mesh.quads) {
    std::array<int, 4> l{};
    for (int k = 0; k < 4; ++k) l[k] = local.at(q[k]);  // the quads' corners are triangles'
    p.quads.push_back(l);
  }
  if (mesh.quad_of.size() == mesh.triangles.size()) p.quad_of = mesh.quad_of;
  p.outline = outline_of(p.triangles);
  const auto [pin_a, pin_b] = conformal_map(x, p);

  // Gauss-Newton on the strain energy, the Jacobian of the residuals by forward differentiation.
  const Triangles m = metrics(x, p);
  bool turned = false;  // an energy in each triangle's flat warp direction
  const std::vector<Mat3> Lt = energy_factors(x, p, mesh, settings, turned);
  const int nd = 2 * static_cast<int>(p.nodes.size());
  double E = energy_of(p, m, Lt, p.uv);
  const double E_scale = std::accumulate(m.area.begin(), m.area.end(), 0.0);
  for (int it = 0; it < settings.max_iterations && E > 1e-30 * E_scale; ++it) {
    std::vector<Eigen::Triplet<double>> H;
    VecX g = VecX::Zero(nd);
    H.reserve(p.triangles.size() * 36 + p.quads.size() * 28 + static_cast<size_t>(nd));
    for (size_t i = 0; i < p.triangles.size(); ++i) {
      if (in_quad(p, i)) continue;
      const auto& t = p.triangles[i];
      Eigen::Matrix<Ad, 6, 1> P;
      const Vec6 pv = corners<3>(p.uv, t);
      for (int k = 0; k < 6; ++k) P[k] = Ad(pv[k], 6, k);
      const Eigen::Matrix<Ad, 3, 1> r = residual<Ad>(P, m.metric[i], Lt[i]);
      Eigen::Matrix<double, 3, 6> J;
      Eigen::Vector3d rv;
      for (int a = 0; a < 3; ++a) J.row(a) = r[a].derivatives().transpose(), rv[a] = r[a].value();
      const Eigen::Matrix<double, 6, 6> JJ = J.transpose() * J;
      const Vec6 Jr = J.transpose() * rv;
      for (int a = 0; a < 6; ++a) {
        const int ia = 2 * t[a / 2] + a % 2;
        g[ia] += Jr[a];
        for (int b = 0; b < 6; ++b) H.emplace_back(ia, 2 * t[b / 2] + b % 2, JJ(a, b));
      }
    }
    for (size_t q = 0; q < p.quads.size(); ++q) {
      Eigen::Matrix<Ad8, 8, 1> P;
      const Vec8 pv = corners<4>(p.uv, p.quads[q]);
      for (int k = 0; k < 8; ++k) P[k] = Ad8(pv[k], 8, k);
      add_cell(quad_residual<Ad8>(P, m.quad_metric[q], Lt[m.quad_triangle[q]]), p.quads[q], g, &H);
    }
    // A touch of damping fixes the flat panel's rigid motions (three zero modes).
    const double mu = 1e-10 * E_scale / static_cast<double>(p.triangles.size());
    for (int k = 0; k < nd; ++k) H.emplace_back(k, k, mu);
    // The warp directions are carried into the flat triangles once, from the conformal map:
    // turning the whole panel then turns the strains against them, a mode Gauss-Newton sees as
    // nearly free (its J^T J is as small as the strains) while the linearised turn stretches
    // the panel, so the line search cut every step to 1/512 and the panel crept (the 100-
    // iteration cap on large orthotropic panels). The panel keeps the conformal map's
    // orientation, in which those directions hold: the pins' turn and shift are held.
    if (turned) {
      double diagonal = 0;
      for (const auto& h : H)
        if (h.row() == h.col()) diagonal = std::max(diagonal, h.value());
      for (int k : {2 * pin_a, 2 * pin_a + 1, 2 * pin_b + 1}) H.emplace_back(k, k, 1e8 * diagonal);
    }
    SparseMatrix K(nd, nd);
    K.setFromTriplets(H.begin(), H.end());
    Eigen::SimplicialLDLT<SparseMatrix> solve(K);
    if (solve.info() != Eigen::Success) break;
    const VecX d = solve.solve(-g);
    double step = 1, E_new = E;
    std::vector<Vec2> trial(p.uv.size());
    for (int half = 0; half < 40; ++half, step /= 2) {
      for (size_t k = 0; k < trial.size(); ++k)
        trial[k] = p.uv[k] + step * d.segment<2>(2 * static_cast<long>(k));
      E_new = energy_of(p, m, Lt, trial);
      if (E_new < E) break;
    }
    p.iterations = it + 1;
    if (!(E_new < E)) break;
    p.uv = trial;
    const double drop = E - E_new;
    E = E_new;
    if (drop < settings.tolerance * E_scale && step == 1) break;
  }

  // Placed with its warp along u from the origin: the given warp directions carried into the
  // flat triangles (d = F^+ a, F = G D^-1 the flat-to-3-D map), or else the longest extent.
  Vec2 mean = Vec2::Zero();
  for (const Vec2& q : p.uv) mean += q;
  mean /= static_cast<double>(p.uv.size());
  Vec2 axis = Vec2::Zero();
  if (mesh.warp.size() == mesh.triangles.size()) {
    for (size_t i = 0; i < p.triangles.size(); ++i) {
      Vec2 d = flat_direction(x, p, i, mesh.warp[i]);
      if (d.norm() == 0) continue;
      d *= m.area[i] / d.norm();
      axis += axis.dot(d) < 0 ? Vec2(-d) : d;  // a direction, not an orientation
    }
    p.warp_from_axes = axis.norm() > 0;
  }
  if (p.warp_from_axes) {
    axis.normalize();
  } else {
    Mat2 cov = Mat2::Zero();
    for (const Vec2& q : p.uv) cov += (q - mean) * (q - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Mat2> eig(cov);
    axis = eig.eigenvectors().col(1);
  }
  Mat2 R;
  R << axis.x(), axis.y(), -axis.y(), axis.x();
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::max());
  for (Vec2& q : p.uv) q = R * (q - mean), lo = lo.cwiseMin(q);
  for (Vec2& q : p.uv) q -= lo;

  // Areas and the strain left in each triangle (in a quadrilateral: at its Gauss points).
  auto largest = [](const Mat2& D, const Mat2& M) {
    const Mat2 Di = D.inverse();
    const Mat2 Eg = (Di.transpose() * M * Di - Mat2::Identity()) / 2;
    return Eigen::SelfAdjointEigenSolver<Mat2>(Eg).eigenvalues().cwiseAbs().maxCoeff();
  };
  std::vector<double> quad_strain(p.quads.size(), 0.0);
  for (size_t q = 0; q < p.quads.size(); ++q) {
    Eigen::Matrix<double, 2, 4> P;
    for (int k = 0; k < 4; ++k) P.col(k) = p.uv[p.quads[q][k]];
    for (int g = 0; g < 4; ++g)
      quad_strain[q] =
          std::max(quad_strain[q], largest(P * quad_gradients(g), m.quad_metric[q][g]));
  }
  for (size_t i = 0; i < p.triangles.size(); ++i) {
    const auto& t = p.triangles[i];
    Mat2 D;
    D << p.uv[t[1]] - p.uv[t[0]], p.uv[t[2]] - p.uv[t[0]];
    p.strain.push_back(in_quad(p, i) ? quad_strain[static_cast<size_t>(p.quad_of[i])]
                                     : largest(D, m.metric[i]));
    p.max_strain = std::max(p.max_strain, p.strain.back());
    p.area_3d += m.area[i];
    p.area_flat += D.determinant() / 2;
  }
  return p;
}

}  // namespace velum
