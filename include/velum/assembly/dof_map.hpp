// Numbering of the unknowns: three translational DOFs per node, of which fixed and prescribed
// components are eliminated. Nodes on a skew symmetry plane get a local frame (rows of R: the
// plane normal and two in-plane axes) and their normal component is eliminated.
// Vectors over all DOFs ("full", 3 x nodes, global Cartesian) and over the equations
// ("reduced", size num_equations(), local frames where a node has one) map both ways.
#pragma once

#include <vector>

#include "velum/model/model.hpp"

namespace velum {

class DofMap {
 public:
  explicit DofMap(const Model& model);

  int num_equations() const { return neq_; }
  int num_nodes() const { return static_cast<int>(eq_.size() / 3); }
  /// Equation of node n, local component c; -1 when eliminated.
  int equation(int n, int c) const { return eq_[3 * n + c]; }
  /// Index into frames() for node n, or -1 (global axes).
  int frame(int n) const { return frame_of_[n]; }
  const Mat3& rotation(int f) const { return frames_[f]; }
  bool has_frames() const { return !frames_.empty(); }

  /// Full vector (global components) from reduced values: eliminated components are left as in
  /// `full` (so prescribed values set beforehand survive).
  void scatter(const VecX& reduced, NodePositions& full) const;
  /// Reduced vector from full global components.
  void gather(const NodePositions& full, VecX& reduced) const;
  /// Components of node n's local frame for a global vector.
  Vec3 to_local(int n, const Vec3& v) const {
    return frame_of_[n] < 0 ? v : frames_[frame_of_[n]] * v;
  }
  Vec3 to_global(int n, const Vec3& v) const {
    return frame_of_[n] < 0 ? v : Vec3(frames_[frame_of_[n]].transpose() * v);
  }

 private:
  std::vector<int> eq_;
  std::vector<int> frame_of_;
  std::vector<Mat3> frames_;
  int neq_ = 0;
};

}  // namespace velum
