// One row per element shape: its name, node counts, edges and face, the file formats' ids (VTK,
// Gmsh, Abaqus) and its mass-lumping rule. Whatever needs a fact about a shape looks its row
// up here (by name or by a file format's id); code templated on the shape (the kernels) reaches
// the compile-time shape of a row through with_shape. Node numbers are local, 0-based, in
// Gmsh's order (corners first, counter-clockwise; then edge midpoints; then the centre).
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string_view>
#include <tuple>
#include <type_traits>

#include "velum/shape/shapes.hpp"

namespace velum::shape {

/// The compile-time shapes (shapes.hpp) that rows name through ShapeInfo::shape (an index here).
using Shapes = std::tuple<Tri3, Tri6, Quad4, Quad8, Quad9, Line2, Line3>;

/// How a row's consistent mass is lumped onto its nodes: row sums, or (where a row sum gives a
/// corner zero or negative mass, tri6 and quad8) the diagonal scaled to the total (HRZ).
enum class Lumping { kRowSum, kHrz };

inline constexpr int kMaxNodes = 9, kMaxCorners = 4, kMaxEdges = 4, kMaxEdgeNodes = 3;
inline constexpr std::array<int, kMaxNodes> kInAbaqusOrder{0, 1, 2, 3, 4, 5, 6, 7, 8};

struct ShapeInfo {
  std::string_view name;  ///< in model files, messages and outputs
  int dimension = 0;      ///< 2: a surface (membranes); 1: a line (cables)
  int shape = 0;          ///< index in Shapes of the compile-time shape
  int nodes = 0;
  int corners = 0;     ///< the first `corners` nodes are the corners
  int num_edges = 0;   ///< surfaces: the boundary edges; lines: the line itself
  int edge_nodes = 0;  ///< nodes per edge: ends first, then the middle node of a quadratic edge
  /// Edge i of a surface runs from corner i to corner i+1 (the face's direction of traversal).
  std::array<std::array<int, kMaxEdgeNodes>, kMaxEdges> edges{};
  int num_faces = 0;  ///< surfaces: 1, the element itself; lines: 0
  /// The face's corners in order: counter-clockwise in the natural coordinates, so that
  /// g1 x g2 (the element's normal) is their right-hand normal.
  std::array<int, kMaxCorners> face{};
  int vtk = 0;                      ///< VTK cell type
  int gmsh = 0;                     ///< Gmsh element type (MSH files)
  std::string_view abaqus;          ///< Abaqus element type with full integration
  std::string_view abaqus_reduced;  ///< its reduced-integration variant (read as full), or empty
  /// Node k (Velum's order) is node from_abaqus[k] of an Abaqus element.
  std::array<int, kMaxNodes> from_abaqus{};
  Lumping lumping = Lumping::kRowSum;

  constexpr bool surface() const { return dimension == 2; }
  constexpr bool line() const { return dimension == 1; }
  /// The nodes' lumped masses m (one per node) from the element's consistent mass Me (nodes x
  /// nodes, either storage order: it is symmetric) by the shape's rule: row sums, or (HRZ) the
  /// diagonal scaled so that it sums to the total.
  void lump(const double* Me, double* m) const {
    const int nn = nodes;
    double total = 0, diag = 0;
    for (int i = 0; i < nn; ++i) {
      double row = 0;
      for (int j = 0; j < nn; ++j) row += Me[i * nn + j];
      m[i] = row;
      total += row;
      diag += Me[i * nn + i];
    }
    if (lumping == Lumping::kHrz)
      for (int i = 0; i < nn; ++i) m[i] = Me[i * nn + i] * total / diag;
  }
  /// The local nodes of edge i (ends first).
  constexpr std::span<const int> edge(int i) const {
    return {edges[static_cast<std::size_t>(i)].data(), static_cast<std::size_t>(edge_nodes)};
  }
};

/// Every shape, in the order model-file messages list them. VTK's quadratic cells and Gmsh's
/// share Velum's node order; Abaqus's too, but for a T3D3 (end, middle, end).
inline constexpr std::array<ShapeInfo, 7> kShapeTable = {{
    {.name = "tri3",
     .dimension = 2,
     .shape = 0,
     .nodes = 3,
     .corners = 3,
     .num_edges = 3,
     .edge_nodes = 2,
     .edges = {{{0, 1}, {1, 2}, {2, 0}}},
     .num_faces = 1,
     .face = {0, 1, 2},
     .vtk = 5,
     .gmsh = 2,
     .abaqus = "M3D3",
     .abaqus_reduced = "",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kRowSum},
    {.name = "tri6",
     .dimension = 2,
     .shape = 1,
     .nodes = 6,
     .corners = 3,
     .num_edges = 3,
     .edge_nodes = 3,
     .edges = {{{0, 1, 3}, {1, 2, 4}, {2, 0, 5}}},
     .num_faces = 1,
     .face = {0, 1, 2},
     .vtk = 22,
     .gmsh = 9,
     .abaqus = "M3D6",
     .abaqus_reduced = "",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kHrz},
    {.name = "quad4",
     .dimension = 2,
     .shape = 2,
     .nodes = 4,
     .corners = 4,
     .num_edges = 4,
     .edge_nodes = 2,
     .edges = {{{0, 1}, {1, 2}, {2, 3}, {3, 0}}},
     .num_faces = 1,
     .face = {0, 1, 2, 3},
     .vtk = 9,
     .gmsh = 3,
     .abaqus = "M3D4",
     .abaqus_reduced = "M3D4R",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kRowSum},
    {.name = "quad8",
     .dimension = 2,
     .shape = 3,
     .nodes = 8,
     .corners = 4,
     .num_edges = 4,
     .edge_nodes = 3,
     .edges = {{{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}}},
     .num_faces = 1,
     .face = {0, 1, 2, 3},
     .vtk = 23,
     .gmsh = 16,
     .abaqus = "M3D8",
     .abaqus_reduced = "M3D8R",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kHrz},
    {.name = "quad9",
     .dimension = 2,
     .shape = 4,
     .nodes = 9,
     .corners = 4,
     .num_edges = 4,
     .edge_nodes = 3,
     .edges = {{{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}}},
     .num_faces = 1,
     .face = {0, 1, 2, 3},
     .vtk = 28,
     .gmsh = 10,
     .abaqus = "M3D9",
     .abaqus_reduced = "M3D9R",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kRowSum},
    {.name = "cable2",
     .dimension = 1,
     .shape = 5,
     .nodes = 2,
     .corners = 2,
     .num_edges = 1,
     .edge_nodes = 2,
     .edges = {{{0, 1}}},
     .num_faces = 0,
     .face = {},
     .vtk = 3,
     .gmsh = 1,
     .abaqus = "T3D2",
     .abaqus_reduced = "",
     .from_abaqus = kInAbaqusOrder,
     .lumping = Lumping::kRowSum},
    {.name = "cable3",
     .dimension = 1,
     .shape = 6,
     .nodes = 3,
     .corners = 2,
     .num_edges = 1,
     .edge_nodes = 3,
     .edges = {{{0, 1, 2}}},
     .num_faces = 0,
     .face = {},
     .vtk = 21,
     .gmsh = 8,
     .abaqus = "T3D3",
     .abaqus_reduced = "",
     .from_abaqus = {0, 2, 1},
     .lumping = Lumping::kRowSum},
}};

/// The row named `name`, or null.
constexpr const ShapeInfo* find(std::string_view name) {
  for (const auto& s : kShapeTable)
    if (s.name == name) return &s;
  return nullptr;
}
/// The row of a Gmsh element type, or null.
constexpr const ShapeInfo* find_gmsh(int gmsh) {
  for (const auto& s : kShapeTable)
    if (s.gmsh == gmsh) return &s;
  return nullptr;
}
/// The row of a VTK cell type, or null.
constexpr const ShapeInfo* find_vtk(int vtk) {
  for (const auto& s : kShapeTable)
    if (s.vtk == vtk) return &s;
  return nullptr;
}
/// The row of an Abaqus element type (either variant, upper case), or null.
constexpr const ShapeInfo* find_abaqus(std::string_view abaqus) {
  for (const auto& s : kShapeTable)
    if (s.abaqus == abaqus || (!s.abaqus_reduced.empty() && s.abaqus_reduced == abaqus)) return &s;
  return nullptr;
}

/// Index of the compile-time shape S in Shapes.
template <class S, std::size_t I = 0>
constexpr int index_of() {
  static_assert(I < std::tuple_size_v<Shapes>, "a shape missing from velum::shape::Shapes");
  if constexpr (std::is_same_v<S, std::tuple_element_t<I, Shapes>>)
    return static_cast<int>(I);
  else
    return index_of<S, I + 1>();
}

/// The (first) row of the compile-time shape S.
template <class S>
constexpr const ShapeInfo& info_of() {
  constexpr int index = index_of<S>();
  for (const auto& s : kShapeTable)
    if (s.shape == index) return s;
  return kShapeTable[0];  // unreachable while every shape has a row (shape_info_test)
}

namespace detail {
template <std::size_t I, class F>
decltype(auto) visit_shape(int index, F& f) {
  using S = std::tuple_element_t<I, Shapes>;
  if constexpr (I + 1 == std::tuple_size_v<Shapes>) {
    return f(S{});
  } else {
    if (index == static_cast<int>(I)) return f(S{});
    return visit_shape<I + 1>(index, f);
  }
}
}  // namespace detail

/// f(S{}) with S the compile-time shape of row `s`: the one place a run-time shape becomes a
/// template argument (f returns the same type for every shape; `if constexpr (S::kDim == 2)`
/// keeps surface-only code away from lines).
template <class F>
decltype(auto) with_shape(const ShapeInfo& s, F&& f) {
  return detail::visit_shape<0>(s.shape, f);
}

}  // namespace velum::shape
