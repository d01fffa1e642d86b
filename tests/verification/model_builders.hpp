// Small structured meshes for the verification tests, built directly through the Model API
// (no model files): parametric patches meshed with quad4, quad9 or tri3 elements (nodes shared
// between patches are merged by position), discs, squares, sphere octants and cable chains,
// plus the static and dynamic drivers the tests share. Units are the caller's.
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/model/model.hpp"

namespace velum::test {

/// Adds nodes to a model, merging nodes that fall on the same position (within `tol`).
class NodeCache {
 public:
  NodeCache(Model& model, double tol) : model_(model), tol_(tol) {}
  int add(const Vec3& x) {
    const std::array<long long, 3> key{std::llround(x.x() / tol_), std::llround(x.y() / tol_),
                                       std::llround(x.z() / tol_)};
    const auto it = index_.find(key);
    if (it != index_.end()) return it->second;
    const int n = model_.add_node(model_.num_nodes() + 1, x);
    index_.emplace(key, n);
    return n;
  }
  Model& model() { return model_; }

 private:
  Model& model_;
  double tol_;
  std::map<std::array<long long, 3>, int> index_;
};

using PatchMap = std::function<Vec3(double u, double v)>;

/// Meshes the image of the unit square [0,1]² under `map` with nu x nv cells of `type`
/// (quad4, quad9 or tri3: each cell split into two triangles). Orientation follows (u, v):
/// the element normal is d map/du x d map/dv. Appends the connectivity to `conn`.
inline void mesh_patch(NodeCache& nodes, const PatchMap& map, int nu, int nv, std::string_view type,
                       std::vector<int>& conn) {
  const int order = type == "quad9" ? 2 : 1;
  const int mu = order * nu + 1, mv = order * nv + 1;
  std::vector<int> grid(static_cast<size_t>(mu) * mv);
  for (int j = 0; j < mv; ++j)
    for (int i = 0; i < mu; ++i)
      grid[j * mu + i] = nodes.add(map(double(i) / (mu - 1), double(j) / (mv - 1)));
  auto at = [&](int i, int j) { return grid[j * mu + i]; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int i0 = order * i, j0 = order * j;
      if (type == "quad4") {
        conn.insert(conn.end(), {at(i0, j0), at(i0 + 1, j0), at(i0 + 1, j0 + 1), at(i0, j0 + 1)});
      } else if (type == "quad9") {
        conn.insert(conn.end(),
                    {at(i0, j0), at(i0 + 2, j0), at(i0 + 2, j0 + 2), at(i0, j0 + 2), at(i0 + 1, j0),
                     at(i0 + 2, j0 + 1), at(i0 + 1, j0 + 2), at(i0, j0 + 1), at(i0 + 1, j0 + 1)});
      } else {  // tri3, diagonals alternating so the mesh has no preferred direction
        const int a = at(i0, j0), b = at(i0 + 1, j0), c = at(i0 + 1, j0 + 1), d = at(i0, j0 + 1);
        if ((i + j) % 2 == 0)
          conn.insert(conn.end(), {a, b, c, a, c, d});
        else
          conn.insert(conn.end(), {a, b, d, b, c, d});
      }
    }
}

/// Quarter disc of radius a in the plane z = 0, x, y >= 0 (O-grid: a central square of
/// half-width a/2 meshed n x n and two ring patches n x n whose outer edge is the arc).
inline std::vector<int> quarter_disc(NodeCache& nodes, double a, int n, std::string_view type) {
  std::vector<int> conn;
  const double c = 0.5 * a, q = 0.25 * std::numbers::pi;
  mesh_patch(
      nodes, [&](double u, double v) { return Vec3(c * u, c * v, 0); }, n, n, type, conn);
  // Ring beside the x axis: u radial, v along the square's edge x = c.
  mesh_patch(
      nodes,
      [&](double u, double v) {
        const Vec3 in(c, c * v, 0), out(a * std::cos(q * v), a * std::sin(q * v), 0);
        return Vec3((1 - u) * in + u * out);
      },
      n, n, type, conn);
  // Ring beside the y axis: u along the square's edge y = c, v radial.
  mesh_patch(
      nodes,
      [&](double u, double v) {
        const double th = 2 * q - q * u;
        const Vec3 in(c * u, c, 0), out(a * std::cos(th), a * std::sin(th), 0);
        return Vec3((1 - v) * in + v * out);
      },
      n, n, type, conn);
  return conn;
}

/// Square [0, a]² in the plane z = 0, n x n cells.
inline std::vector<int> square(NodeCache& nodes, double a, int n, std::string_view type) {
  std::vector<int> conn;
  mesh_patch(
      nodes, [&](double u, double v) { return Vec3(a * u, a * v, 0); }, n, n, type, conn);
  return conn;
}

/// Octant x, y, z >= 0 of the sphere of radius R: three patches meeting at (1,1,1)/√3, each
/// n x n, nodes projected onto the sphere; normals point outwards.
inline std::vector<int> sphere_octant(NodeCache& nodes, double R, int n, std::string_view type) {
  std::vector<int> conn;
  const Vec3 centre = Vec3::Ones().normalized();
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k), e1 = Vec3::Unit((k + 1) % 3), e2 = Vec3::Unit((k + 2) % 3);
    const Vec3 A = e, B = (e + e1).normalized(), C = centre, D = (e + e2).normalized();
    mesh_patch(
        nodes,
        [&](double u, double v) {
          const Vec3 p = (1 - u) * (1 - v) * A + u * (1 - v) * B + u * v * C + (1 - u) * v * D;
          return Vec3(R * p.normalized());
        },
        n, n, type, conn);
  }
  return conn;
}

/// Straight chain of n cable2 or cable3 elements from X0 to X1; returns the connectivity and
/// fills `chain` with the node indices in order along the cable.
inline std::vector<int> cable_chain(NodeCache& nodes, const Vec3& X0, const Vec3& X1, int n,
                                    std::string_view type, std::vector<int>& chain) {
  const int order = type == "cable3" ? 2 : 1;
  chain.clear();
  for (int i = 0; i <= order * n; ++i)
    chain.push_back(nodes.add(X0 + (X1 - X0) * (double(i) / (order * n))));
  std::vector<int> conn;
  for (int e = 0; e < n; ++e) {
    const int i0 = order * e;
    if (order == 1)
      conn.insert(conn.end(), {chain[i0], chain[i0 + 1]});
    else
      conn.insert(conn.end(), {chain[i0], chain[i0 + 2], chain[i0 + 1]});
  }
  return conn;
}

/// Nodes whose reference position satisfies `pred`.
inline std::vector<int> nodes_where(const Model& m, const std::function<bool(const Vec3&)>& pred) {
  std::vector<int> out;
  for (int n = 0; n < m.num_nodes(); ++n)
    if (pred(m.X.col(n))) out.push_back(n);
  return out;
}

/// Node nearest to P.
inline int nearest_node(const Model& m, const Vec3& P) {
  int best = 0;
  for (int n = 1; n < m.num_nodes(); ++n)
    if ((m.X.col(n) - P).norm() < (m.X.col(best) - P).norm()) best = n;
  return best;
}

inline int add_membrane(Model& m, std::string_view type, std::vector<int> conn, const SheetLaw& law,
                        double density, double thickness,
                        shape::Integration integration = shape::Integration::kGauss) {
  BlockSetupReport report;
  m.blocks.push_back(make_membrane_block(type, "sheet", std::move(conn), m.X, law, density,
                                         thickness, nullptr, integration, report));
  return static_cast<int>(m.blocks.size()) - 1;
}

inline int add_cable(Model& m, std::string_view type, std::vector<int> conn, const CableLaw& law,
                     double density, double area,
                     shape::Integration integration = shape::Integration::kGauss) {
  BlockSetupReport report;
  m.blocks.push_back(make_cable_block(type, "cable", std::move(conn), m.X, law, density, area,
                                      integration, report));
  return static_cast<int>(m.blocks.size()) - 1;
}

/// Pressure on every element of block b, scaled by time function f (-1: constant).
inline void add_pressure(Model& m, int b, double p, int f = -1) {
  PressureLoad load;
  load.block = b;
  load.value = p;
  load.function = f;
  for (int e = 0; e < m.blocks[b]->size(); ++e) load.elements.push_back(e);
  m.pressures.push_back(std::move(load));
}

inline int add_ramp(Model& m, double duration) {
  TimeFunction f;
  f.kind = TimeFunction::Kind::kRamp;
  f.duration = duration;
  f.name = "ramp";
  m.functions.push_back(f);
  return static_cast<int>(m.functions.size()) - 1;
}

/// Reduced state from full nodal displacements (and zero velocity and acceleration).
inline State state_from(const MechanicalSystem& sys, const NodePositions& U) {
  State s;
  sys.dofs().gather(U, s.u);
  s.v = VecX::Zero(sys.size());
  s.a = VecX::Zero(sys.size());
  return s;
}

struct StaticRun {
  TimeLoopResult loop;
  std::vector<StepReport> reports;  ///< one per accepted step
};

/// Static load stepping from the state `s` (an initial guess: flat membranes and straight
/// cables need one with some tension) over t in (0, 1] in `steps` equal steps.
inline StaticRun run_static(MechanicalSystem& sys, State& s, int steps,
                            const NewtonSettings& newton = {}) {
  StaticNewton integrator;
  integrator.newton = newton;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0;
  loop.t_end = 1;
  loop.step = 1.0 / steps;
  StaticRun out;
  out.loop =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State&) {
        out.reports.push_back(*st.report);
        return true;
      });
  return out;
}

/// Relative error in percent.
inline double percent(double measured, double exact) {
  return 100.0 * std::abs(measured - exact) / std::abs(exact);
}

}  // namespace velum::test
