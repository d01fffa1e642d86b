// Numbering of the unknowns: three translational DOFs per node, of which fixed and prescribed
// components are eliminated. Nodes on a skew symmetry plane get a local frame (rows of R: the
// plane normal and two in-plane axes) and their normal component is eliminated.
// Vectors over all DOFs ("full", 3 x nodes, global Cartesian) and over the equations
// ("reduced", size num_equations(), local frames where a node has one) map both ways.
//
// On a process's piece of a shared model (docs/parallel.md, model_piece.hpp) the nodes are the
// piece's and the global numbering is the whole model's, made before it was shared
// (ModelPiece::equation); each process holds its local equations (EquationLayout: the ones it
// owns, then its ghosts) and equation() answers in those.
#pragma once

#include <vector>

#include "velum/model/model.hpp"
#include "velum/parallel/equation_layout.hpp"

namespace velum {

class DofMap {
 public:
  explicit DofMap(const Model& model);

  /// This process's equations (all of them on one process).
  int num_equations() const { return layout_.local(); }
  /// Equations over every process.
  int global_equations() const { return neq_; }
  int num_nodes() const { return static_cast<int>(eq_.size() / 3); }
  /// Equation of node n, local component c, in this process's local numbering; -1 when
  /// eliminated.
  int equation(int n, int c) const { return local_.empty() ? eq_[3 * n + c] : local_[3 * n + c]; }
  /// equation(n, c) for every node and component (3 n + c), as one array.
  const int* equations() const { return local_.empty() ? eq_.data() : local_.data(); }
  /// The same in the global numbering.
  int global_equation(int n, int c) const { return eq_[3 * n + c]; }
  /// Where the global equations start on each process when owned in whole nodes where
  /// possible (as PETSc splits a matrix of block size 3): count() + 1 entries.
  std::vector<long> row_start() const;
  /// The same for `count` processes (the split of a model into parts on one process).
  std::vector<long> row_start(int count) const;
  /// Equations come three to a node (every node has all or none).
  bool whole_nodes() const { return whole_nodes_; }
  const EquationLayout& layout() const { return layout_; }
  /// Index into frames() for node n, or -1 (global axes).
  int frame(int n) const { return frame_of_[n]; }
  const Mat3& rotation(int f) const { return frames_[f]; }
  bool has_frames() const { return !frames_.empty(); }

  /// Full vector (global components) from reduced values: eliminated components are left as in
  /// `full` (so prescribed values set beforehand survive).
  void scatter(const VecX& reduced, NodePositions& full) const;
  /// Reduced vector from full global components.
  void gather(const NodePositions& full, VecX& reduced) const;
  /// gather(a − b, reduced) without the full difference (no temporary; a pass shared
  /// between the threads where no node has a frame of its own).
  void gather_difference(const NodePositions& a, const NodePositions& b, VecX& reduced) const;
  /// Zeroes the components that have equations (in each node's frame), keeping the
  /// eliminated ones: a reaction from internal minus external forces.
  void keep_eliminated(NodePositions& full) const;
  /// Components of node n's local frame for a global vector.
  Vec3 to_local(int n, const Vec3& v) const {
    return frame_of_[n] < 0 ? v : frames_[frame_of_[n]] * v;
  }
  Vec3 to_global(int n, const Vec3& v) const {
    return frame_of_[n] < 0 ? v : Vec3(frames_[frame_of_[n]].transpose() * v);
  }

 private:
  // A piece's numbering: the global one it was given, its local equations (a collective call).
  void take_piece(const ModelPiece& piece, const std::vector<char>& eliminated);

  std::vector<int> eq_;     // global
  std::vector<int> local_;  // local (empty: one process, the same as eq_)
  EquationLayout layout_;
  bool whole_nodes_ = true;
  std::vector<int> frame_of_;
  std::vector<Mat3> frames_;
  int neq_ = 0;
};

}  // namespace velum
