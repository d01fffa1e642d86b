// The shape table (shape_info.hpp): every row consistent with its compile-time shape and with
// itself: ids that find the row again (VTK, Gmsh, Abaqus), edges on valid nodes running round
// a counter-clockwise face, mid-edge nodes at their edge's middle, Abaqus orders that are
// permutations, and HRZ lumping exactly where a row sum would give a node no positive mass.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "velum/shape/shape_info.hpp"

namespace velum::shape {
namespace {

TEST(ShapeInfo, EveryLookupFindsTheRowAgain) {
  std::set<std::string_view> names;
  std::set<int> vtk, gmsh;
  for (const ShapeInfo& s : kShapeTable) {
    EXPECT_EQ(find(s.name), &s) << s.name;
    EXPECT_EQ(find_vtk(s.vtk), &s) << s.name;
    EXPECT_EQ(find_gmsh(s.gmsh), &s) << s.name;
    EXPECT_EQ(find_abaqus(s.abaqus), &s) << s.name;
    if (!s.abaqus_reduced.empty()) {
      EXPECT_EQ(find_abaqus(s.abaqus_reduced), &s) << s.name;
    }
    EXPECT_TRUE(names.insert(s.name).second) << s.name;
    EXPECT_TRUE(vtk.insert(s.vtk).second) << s.name;
    EXPECT_TRUE(gmsh.insert(s.gmsh).second) << s.name;
  }
  EXPECT_EQ(find("tri4"), nullptr);
  EXPECT_EQ(find_gmsh(4), nullptr);  // a tetrahedron
  EXPECT_EQ(find_vtk(10), nullptr);
  EXPECT_EQ(find_abaqus("S4R"), nullptr);
  EXPECT_EQ(find_abaqus(""), nullptr);
}

TEST(ShapeInfo, RowsMatchTheirCompileTimeShape) {
  for (const ShapeInfo& s : kShapeTable)
    with_shape(s, [&]<class S>(S) {
      EXPECT_EQ(S::kNodes, s.nodes) << s.name;
      EXPECT_EQ(S::kDim, s.dimension) << s.name;
      EXPECT_EQ(&info_of<S>(), &s) << s.name;  // one row per compile-time shape here
    });
  EXPECT_EQ(info_of<Tri6>().name, "tri6");
  EXPECT_EQ(info_of<Line3>().name, "cable3");
}

TEST(ShapeInfo, EdgesRunRoundACounterClockwiseFace) {
  for (const ShapeInfo& s : kShapeTable) {
    ASSERT_LE(s.nodes, kMaxNodes);
    ASSERT_LE(s.num_edges, kMaxEdges);
    ASSERT_TRUE(s.edge_nodes == 2 || s.edge_nodes == 3) << s.name;
    std::set<int> mids;
    for (int i = 0; i < s.num_edges; ++i) {
      const auto ed = s.edge(i);
      ASSERT_EQ(static_cast<int>(ed.size()), s.edge_nodes);
      for (int k = 0; k < s.edge_nodes; ++k) {
        EXPECT_GE(ed[k], 0) << s.name;
        EXPECT_LT(ed[k], s.nodes) << s.name;
      }
      EXPECT_LT(ed[0], s.corners) << s.name;  // ends first, and they are corners
      EXPECT_LT(ed[1], s.corners) << s.name;
      if (s.edge_nodes == 3) {
        EXPECT_GE(ed[2], s.corners) << s.name;
        EXPECT_TRUE(mids.insert(ed[2]).second) << s.name << ": a mid node on two edges";
      }
    }
    // No node besides the corners and the edges' middles but a quad9's centre.
    const int centre = s.name == "quad9" ? 1 : 0;
    EXPECT_EQ(s.corners + static_cast<int>(mids.size()) + centre, s.nodes) << s.name;
    if (s.line()) {
      EXPECT_EQ(s.num_faces, 0) << s.name;
      EXPECT_EQ(s.num_edges, 1) << s.name;
      EXPECT_EQ(s.edge_nodes, s.nodes) << s.name;
      EXPECT_EQ(s.corners, 2) << s.name;
      continue;
    }
    ASSERT_TRUE(s.surface()) << s.name;
    EXPECT_EQ(s.num_faces, 1) << s.name;
    EXPECT_EQ(s.num_edges, s.corners) << s.name;
    for (int i = 0; i < s.corners; ++i) {
      EXPECT_EQ(s.edge(i)[0], s.face[static_cast<size_t>(i)]) << s.name;
      EXPECT_EQ(s.edge(i)[1], s.face[static_cast<size_t>((i + 1) % s.corners)]) << s.name;
    }
    with_shape(s, [&]<class S>(S) {
      if constexpr (S::kDim == 2) {
        const auto xi = S::nodes();
        // Mid-edge nodes at the middle of their edge's ends.
        for (int i = 0; i < s.num_edges; ++i) {
          const auto ed = s.edge(i);
          if (ed.size() < 3) continue;
          for (int d = 0; d < 2; ++d)
            EXPECT_DOUBLE_EQ(xi[ed[2]][d], 0.5 * (xi[ed[0]][d] + xi[ed[1]][d])) << s.name;
        }
        // The face counter-clockwise in ξ (positive signed area) ...
        double area = 0;
        for (int i = 0; i < s.corners; ++i) {
          const auto& a = xi[s.face[static_cast<size_t>(i)]];
          const auto& b = xi[s.face[static_cast<size_t>((i + 1) % s.corners)]];
          area += a[0] * b[1] - a[1] * b[0];
        }
        EXPECT_GT(area, 0) << s.name;
        // ... and g1 x g2 along +z for the element laid flat on its natural coordinates.
        typename S::Values N;
        typename S::Derivs dN;
        const double c = S::kTriangle ? 1.0 / 3 : 0.0;
        S::eval(c, c, N, dN);
        Eigen::Matrix<double, 3, S::kNodes> X = Eigen::Matrix<double, 3, S::kNodes>::Zero();
        for (int k = 0; k < S::kNodes; ++k) X.col(k) << xi[k][0], xi[k][1], 0;
        const Eigen::Matrix<double, 3, 2> G = X * dN;
        EXPECT_GT(G.col(0).cross(G.col(1)).z(), 0) << s.name;
      }
    });
  }
}

TEST(ShapeInfo, AbaqusOrdersArePermutations) {
  for (const ShapeInfo& s : kShapeTable) {
    std::vector<int> order(s.from_abaqus.begin(), s.from_abaqus.begin() + s.nodes);
    std::sort(order.begin(), order.end());
    for (int k = 0; k < s.nodes; ++k) EXPECT_EQ(order[static_cast<size_t>(k)], k) << s.name;
  }
  // A T3D3 lists end, middle, end; Velum (Gmsh) ends, then the middle.
  EXPECT_EQ(find_abaqus("T3D3")->from_abaqus[1], 2);
  EXPECT_EQ(find_abaqus("T3D3")->from_abaqus[2], 1);
}

TEST(ShapeInfo, HrzLumpingWhereARowSumGivesANodeNoPositiveMass) {
  // The row sum of the consistent mass of node i is ∫ N_i (the N_j summing to one).
  for (const ShapeInfo& s : kShapeTable)
    with_shape(s, [&]<class S>(S) {
      constexpr auto rule = S::rule();
      typename S::Values N, integral = S::Values::Zero();
      for (int q = 0; q < S::kPoints; ++q) {
        if constexpr (S::kDim == 2) {
          typename S::Derivs dN;
          S::eval(rule.xi[q][0], rule.xi[q][1], N, dN);
        } else {
          typename S::Values dN;
          S::eval(rule.xi[q][0], N, dN);
        }
        integral += rule.w[q] * N;
      }
      const bool hrz = s.lumping == Lumping::kHrz;
      EXPECT_EQ(hrz, integral.minCoeff() < 1e-12) << s.name;
    });
}

}  // namespace
}  // namespace velum::shape
