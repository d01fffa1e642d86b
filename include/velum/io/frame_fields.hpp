// The per-cell and per-node values of one output time (docs/model-format.md, "Frames"): what
// the ParaView frames carry and what the summary's extremes are taken from. Cell values are
// evaluated at each element's centre; a float field that does not apply to a cell's kind
// (membrane or cable) is NaN there, which ParaView shows as absent. Units are the model's own;
// angles in degrees.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "velum/model/model.hpp"

namespace velum::io {

/// One float cell array: `components` values per cell, the cells evaluate_cells was given
/// (a process's own, in block order: every cell on one process).
struct CellArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  bool averaged = false;  ///< also written as point data, averaged from the cells around
};

/// Indices into FrameFields::cells of the arrays the summary's extremes read.
enum CellField : int {
  kTrueStressMax,
  kTrueStressMin,
  kStressDirMax,
  kStressDirMin,
  kFiberAngleChange,
  kCableForce,
  kStress11,
  kStress22,
  kStress12,
  kForcePerLengthMax,
  kForcePerLengthMin,
  kForcePerLength11,
  kForcePerLength22,
  kForcePerLength12,
  kStrain11,
  kStrain22,
  kStrain12,
  kStretchMax,
  kStretchMin,
  kSheetAxis1,
  kSheetAxis2,
  kSheetNormal,
  kFiberDir1,
  kFiberDir2,
  kWrinkleDir,  // present only when a section wrinkles
  kCellFieldCount
};

struct FrameFields {
  std::vector<CellArray> cells;             ///< indexed by CellField (kWrinkleDir may be absent)
  std::vector<std::int32_t> wrinkle_state;  ///< when a section wrinkles: 0 taut, 1, 2; cables 0
};

/// The cell values of `model` at current positions x (threads over the elements of a block):
/// those of the elements `own` lists (per block, ascending: every element on one process),
/// one after the other in that order (no entry for the others: under mpirun a process holds
/// arrays of its own cells only). A field that does not apply to a cell's kind is NaN there.
/// `extremes_only`: only the arrays the summary's extremes read (kTrueStressMax,
/// kForcePerLengthMax, kCableForce) hold values, the others are empty (a run without frames).
FrameFields evaluate_cells(const Model& model, const NodePositions& x,
                           const std::vector<std::vector<int>>& own, bool extremes_only = false);

/// The labels of the integer cell fields `element_set` and `material`: each block's value is
/// an index into these names (model order of first appearance).
struct CellLabels {
  std::vector<std::string> sets, materials;
  std::vector<std::int32_t> set_of_block, material_of_block;
};
CellLabels cell_labels(const Model& model, const std::vector<std::string>& block_materials);

/// Reference-area weights of the membrane cells `own` lists (per block, ascending; one per
/// listed cell, in that order, 0 for cables) for averaging to nodes, and their sum at each node (0
/// at nodes none of them touches). Under mpirun node_weight is this process's share until the owner
/// completes it at the shared nodes (Assembler::sum_at_shared_nodes), as the sums below.
struct NodalAverage {
  std::vector<double> cell_weight, node_weight;
  NodalAverage(const Model& model, const std::vector<std::vector<int>>& own);
  /// The area-weighted sums at the nodes of a scalar cell array over the `own` cells (the
  /// array holds the `own` cells' values, as evaluate_cells).
  std::vector<double> sums(const Model& model, const std::vector<std::vector<int>>& own,
                           const std::vector<double>& cell) const;
  /// Sums (complete) to point values: the area-weighted mean over the membrane cells holding
  /// the node (corner and mid-side nodes alike); NaN where no membrane does.
  void divide(std::vector<double>& sum) const;
};

}  // namespace velum::io
