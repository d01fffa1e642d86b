// Arc length on a sphere inflated by an enclosed gas (an SVK skin, the octant closed by its
// symmetry planes, p = p0 (m(t) V0 / V)^γ): its corrections solve with the chamber's rank-one
// p(V) coupling, as the static Newton's do, so they converge quadratically and the path ends on
// the static solution at the same load level.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "velum/analysis/analysis.hpp"
#include "velum/io/model_reader.hpp"

namespace velum {
namespace {

// The unit sphere's octant in tri3, n divisions a side: node (i, j) at (i, j, n − i − j)
// normalised, triangles ordered so that their normals point out of the gas. The gas amount
// rises from gauge zero at t = 0 to m = 1 at t = 1 and on beyond it (the path's load rate
// is taken on either side of a point).
std::string gas_sphere_yaml(int n) {
  std::map<std::pair<int, int>, int> id;
  std::string nodes, elements, px, py, pz;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const int k = n - i - j, label = static_cast<int>(id.size()) + 1;
      const double l = std::sqrt(double(i * i + j * j + k * k));
      id[{i, j}] = label;
      nodes += fmt::format("{}[{}, {:.17g}, {:.17g}, {:.17g}]", nodes.empty() ? "" : ", ", label,
                           i / l, j / l, k / l);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const int a = id[{i, j}], b = id[{i + 1, j}], c = id[{i, j + 1}];
      elements += fmt::format("{}[{}, {}, {}]", elements.empty() ? "" : ", ", a, b, c);
      if (i + j < n - 1) elements += fmt::format(", [{}, {}, {}]", b, id[{i + 1, j + 1}], c);
    }
  for (int k = 0; k <= n; ++k) {
    const char* sep = k ? ", " : "";
    px += fmt::format("{}{}", sep, id[{0, k}]);
    py += fmt::format("{}{}", sep, id[{k, 0}]);
    pz += fmt::format("{}{}", sep, id[{k, n - k}]);
  }
  const double m0 = std::pow(1e5 / 5.5e5, 1 / 1.4);  // the amount at which p = p_ambient
  return fmt::format(R"(mesh:
  nodes: [{}]
  elements:
    - {{set: skin, type: tri3, connectivity: [{}]}}
  node_sets: {{px: [{}], py: [{}], pz: [{}]}}
materials:
  svk: {{type: isotropic, E: 1.0e9, nu: 0.3, density: 1000.0}}
sections:
  - {{elements: skin, material: svk, thickness: 1.0e-3}}
boundary:
  - {{nodes: px, symmetry: {{normal: [1, 0, 0]}}}}
  - {{nodes: py, symmetry: {{normal: [0, 1, 0]}}}}
  - {{nodes: pz, symmetry: {{normal: [0, 0, 1]}}}}
loads:
  - {{type: gas, elements: skin, initial_pressure: 5.5e5, ambient: 1.0e5, gamma: 1.4, amount: fill, origin: [0, 0, 0]}}
functions:
  fill: {{type: table, points: [[0, {:.17g}], [1, 1], [2, {:.17g}]]}}
analysis:
  type: static
  time: {{end: 1.0, step: 0.125}}
)",
                     nodes, elements, px, py, pz, m0, 2 - m0);
}

struct Traced {
  AnalysisResult result;
  NodePositions last;  // the displacements at the last step
  double t = 0;
  int most_iterations = 0;  // in one step
};

Traced trace(PathSettings::Method method) {
  io::ModelInput in = io::read_model_text(gas_sphere_yaml(4), {"gas sphere", {}});
  in.analysis.path.method = method;
  MechanicalSystem sys(in.model);
  Traced out;
  out.result = run_analysis(sys, in.analysis, [&](const StepSnapshot& snap) {
    out.last = sys.displacements(snap.step.t, snap.state.u);
    out.t = snap.step.t;
    out.most_iterations = std::max(out.most_iterations, snap.step.iterations);
    return true;
  });
  return out;
}

TEST(PathFollowing, ArcLengthWithAGasChamberEndsOnTheStaticSolution) {
  const Traced load = trace(PathSettings::Method::kLoadControl);
  const Traced arc = trace(PathSettings::Method::kArcLength);
  ASSERT_TRUE(load.result.loop.completed) << load.result.loop.reason;
  ASSERT_TRUE(arc.result.loop.completed) << arc.result.loop.reason;
  EXPECT_EQ(arc.t, 1.0);
  const double size = load.last.cwiseAbs().maxCoeff();
  ASSERT_GT(size, 0.05);  // the radius grows by 8 %
  EXPECT_LE((arc.last - load.last).cwiseAbs().maxCoeff(), 1e-8 * size);
  // Quadratic convergence: without the p(V) coupling in its solves the first arc step took
  // 12 corrections (linear, a fifth of the residual each) and the run 19 cut-backs.
  EXPECT_LE(arc.most_iterations, 6);
  EXPECT_EQ(arc.result.loop.cutbacks, 0);
}

}  // namespace
}  // namespace velum
