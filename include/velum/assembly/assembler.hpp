// Parallel assembly of element contributions into global vectors and one sparse matrix
// pattern (built once). Elements of a block are coloured so that no two elements of a colour
// share a node: threads then write disjoint entries, without locks, and every entry receives
// its contributions in the same order whatever the thread count (deterministic results).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "velum/assembly/dof_map.hpp"

namespace velum {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

class Assembler {
 public:
  Assembler(const Model& model, const DofMap& dofs);

  /// A matrix over the equations with the full pattern and zero values (the pattern is
  /// rebuilt from the mesh: the assembler keeps only the positions it scatters to).
  SparseMatrix make_matrix() const;
  /// The same, into A (its storage reused where it fits, no temporary copy).
  void make_matrix(SparseMatrix& A) const;
  /// Stored entries of that pattern.
  Eigen::Index nonzeros() const { return nonzeros_; }

  /// Internal forces (full, global; overwritten) and, if K != null, the tangent (values
  /// overwritten, pattern of make_matrix()).
  void internal(const NodePositions& x, NodePositions& F, SparseMatrix* K) const;
  /// Follower pressure load i of the model at pressure p: forces added to Fext; the load
  /// stiffness subtracted from K when K != null (K then becomes unsymmetric).
  void pressure(int i, double p, const NodePositions& x, NodePositions& Fext,
                SparseMatrix* K) const;
  /// Consistent mass (values overwritten) and lumped nodal masses (row sum; HRZ for tri6 and
  /// quad8, whose row sums are not all positive), point masses included in both.
  void mass(SparseMatrix* M, VecX* lumped) const;  ///< either may be null
  /// Nodal forces of gravity g: consistent mass times g (point masses included).
  NodePositions gravity_forces(const Vec3& g) const;

  int num_colors(int block) const { return static_cast<int>(colors_[block].size()); }

 private:
  struct Colored {
    std::vector<std::vector<int>> colors;  // element lists
  };
  /// Adds the element vectors of the listed colours to F and matrix_sign times their matrices
  /// to K (when tangent).
  template <class Compute>
  void run(int block, const std::vector<std::vector<int>>& colors, const Compute& compute,
           bool tangent, NodePositions& F, SparseMatrix* K, double matrix_sign) const;

  struct ElementBuffers {
    std::vector<double> r;
    // Aligned: blocks write element matrices through fixed-size Eigen references into it.
    std::vector<double, Eigen::aligned_allocator<double>> K;
  };

  const Model& model_;
  const DofMap& dofs_;
  int neq_ = 0;
  Eigen::Index nonzeros_ = 0;
  std::vector<std::vector<std::vector<int>>> colors_;           // per block
  std::vector<std::vector<int>> scatter_;                       // per block: ne x dofs² positions
  std::vector<std::vector<std::vector<int>>> pressure_colors_;  // per pressure load
  int max_dofs_ = 0;
  mutable std::vector<ElementBuffers> buffers_;  // one per thread, reused across calls
};

}  // namespace velum
