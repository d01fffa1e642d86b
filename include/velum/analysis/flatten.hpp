// Flattening of a surface panel into the plane (cutting patterns, docs/patterns.md): a
// least-squares conformal map, then the flat state of least membrane strain energy when the
// flat panel is pulled onto its 3-D shape.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "velum/math/types.hpp"

namespace velum {

using NodePositions = Eigen::Matrix<double, 3, Eigen::Dynamic>;

/// A panel's triangles on the nodes of its 3-D shape (corner nodes, indices into `x`).
struct PanelMesh {
  std::vector<std::array<int, 3>> triangles;
  /// Per triangle: the warp (the section's first sheet axis) on the 3-D shape, or empty: the
  /// flat panel's warp u then runs along its longest extent.
  std::vector<Vec3> warp;
  /// Quadrilaterals (corner nodes in the element's order) whose strain is measured as a quad4
  /// element measures it: at its 2 x 2 Gauss points on the bilinear surface, so that the
  /// panel sewn from the flat quads is stress-free where the flattening left no strain.
  /// quad_of[i]: the quadrilateral triangle i splits (its outline and output), -1 for a
  /// triangle of its own. Both empty: triangles only.
  std::vector<std::array<int, 4>> quads{};
  std::vector<int> quad_of{};
};

struct FlattenSettings {
  double nu = 0.3;  ///< Poisson's ratio of the isotropic energy minimised without `stiffness`
  /// The panel's law at zero strain in its sheet axes (Voigt, engineering shear; any scale):
  /// with PanelMesh::warp the energy is the law's, the axes carried into each flat triangle.
  /// Zero: isotropic with `nu`.
  Mat3 stiffness = Mat3::Zero();
  int max_iterations = 100;  ///< Gauss-Newton iterations
  double tolerance = 1e-13;  ///< relative energy decrease at which the iterations stop
};

struct FlatPanel {
  std::vector<int> nodes;                     ///< model node indices, the order of uv
  std::vector<Vec2> uv;                       ///< flat coordinates (before compensation)
  std::vector<std::array<int, 3>> triangles;  ///< on local indices into nodes
  std::vector<std::array<int, 4>> quads;      ///< on local indices (PanelMesh::quads)
  std::vector<int> quad_of;                   ///< per triangle, as PanelMesh::quad_of
  std::vector<int> outline;  ///< local node indices around the boundary, counter-clockwise
  /// per triangle: the largest |principal Green strain| (of its quadrilateral's Gauss points)
  std::vector<double> strain;
  double area_3d = 0, area_flat = 0, max_strain = 0;
  int iterations = 0;
  bool warp_from_axes = false;  ///< u is the mean of the given warp directions (PanelMesh::warp)
};

/// Why the triangles are not one disc (several pieces, holes: Euler characteristic, an edge
/// shared by more than two triangles), or an empty string.
std::string disc_problem(const PanelMesh& mesh, int num_nodes);

/// The flat panel of `mesh` (a disc) on the shape `x`. Throws std::invalid_argument when the
/// panel is not a disc (disc_problem).
FlatPanel flatten_panel(const NodePositions& x, const PanelMesh& mesh,
                        const FlattenSettings& settings = {});

/// The energy minimised, for tests: sum over triangles of A_flat/2 e^T C e (e the Green strain
/// of the flat triangle pulled onto the 3-D one, Voigt with engineering shear, C plane stress
/// with E = 1), quadrilaterals summed over their Gauss points instead, and its gradient with
/// respect to the flat coordinates (2 per node of uv).
double flattening_energy(const NodePositions& x, const FlatPanel& panel, double nu, VecX* gradient);

}  // namespace velum
