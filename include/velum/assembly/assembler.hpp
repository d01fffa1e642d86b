// Parallel assembly of element contributions into global vectors and one sparse matrix
// pattern (built once). Elements of a block are coloured so that no two elements of a colour
// share a node: threads then write disjoint entries, without locks, and every entry receives
// its contributions in the same order whatever the thread count (deterministic results).
//
// On several MPI processes (docs/parallel.md) the model is a process's piece (share_model,
// model_piece.hpp): its own elements and the nodes it holds. It computes only those: its
// matrices hold its share of the sum (their pattern: its elements' couplings), the solver adds
// the shares; its per-node vectors (forces, lumped masses, gas gradients) are over the
// piece's nodes, summed over the processes here where processes share nodes (outside a
// LocalShare), so that every process holds the total at every node it holds.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "velum/assembly/dof_map.hpp"
#include "velum/assembly/element_scatter.hpp"
#include "velum/math/sparse.hpp"
#include "velum/parallel/element_partition.hpp"
#include "velum/parallel/model_piece.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {

/// Loops over every stored entry of a matrix run on all threads above this many entries
/// (below it a parallel region costs more than it saves).
inline constexpr Eigen::Index kParallelMatrixEntries = 200000;

/// A ← a A + b B on A's stored values (B on A's pattern, or null: A ← a A). a = 0 overwrites
/// A whatever it held.
void combine_values(SparseMatrix& A, double a, const SparseMatrix* B, double b);

class Assembler {
 public:
  /// Every element of `model`, or, on a piece of a shared model, its own (the piece's
  /// partition); matrices and equation vectors over `dofs`' local equations.
  Assembler(const Model& model, const DofMap& dofs);

  /// A matrix over the equations with the full pattern and zero values (the pattern is
  /// rebuilt from the mesh, but for the first call: the assembler keeps only the positions it
  /// scatters to).
  SparseMatrix make_matrix() const;
  /// The same, into A (its storage reused where it fits, no temporary copy).
  void make_matrix(SparseMatrix& A) const;
  /// Stored entries of that pattern.
  Eigen::Index nonzeros() const { return nonzeros_; }
  /// Node pairs coupled beyond the elements (loads' couplings: a contact's node and the
  /// nodes of its face, LoadTerm::couplings), each pair once, either order: the pattern
  /// becomes the elements' couplings and these (3 x 3 node blocks both ways). Rebuilds the
  /// pattern and the scatter positions when the set differs from the one in place (matrices
  /// made before then no longer fit: make them again); nothing otherwise.
  void set_couplings(std::vector<std::array<int, 2>> pairs);
  /// Changes whenever set_couplings changes the pattern (0: the elements' alone, never
  /// changed); different for every pattern made, over all assemblers. Keys a solver's
  /// symbolic analysis (LinearSolver::refactorize).
  long pattern_revision() const { return revision_; }
  /// Per equation, where its diagonal entry sits in the values of the matrices make_matrix()
  /// makes (−1: none).
  const std::vector<int>& diagonal_positions() const { return diagonal_at_; }

  /// Internal forces (full, global; overwritten) and, if K != null, the tangent (values
  /// overwritten, pattern of make_matrix()).
  void internal(const NodePositions& x, NodePositions& F, SparseMatrix* K) const;
  /// The same, with a follower pressure block_pressure[b] on every element of block b
  /// (0: none) computed in the block's pass: forces overwrite Fp, the load stiffness is
  /// subtracted from K in the same scatter as the tangent (one pass over the matrix instead
  /// of two).
  void internal(const NodePositions& x, NodePositions& F, SparseMatrix* K,
                std::span<const double> block_pressure, NodePositions& Fp) const;
  /// The same forces (no tangent) for an explicit step, through the blocks' explicit fast
  /// path (SurfaceBlock::explicit_forces): equal to internal()'s to round-off.
  void explicit_forces(const NodePositions& x, NodePositions& F,
                       std::span<const double> block_pressure, NodePositions& Fp) const;
  /// Follower pressure load i of the model (Model::pressures) at pressure p: forces added to
  /// Fext; the load stiffness subtracted from K when K != null. A convenience over the
  /// load's own term (load/pressure_load.hpp), which binds it anew at every call.
  void pressure(int i, double p, const NodePositions& x, NodePositions& Fext,
                SparseMatrix* K) const;

  /// Element loads (pressures, gas) go through the same coloured passes as the internal
  /// forces. Per colour, element lists of chunks no two of which share a node.
  using ElementColors = std::vector<std::vector<int>>;
  /// The colouring of the listed elements of block `block` this process computes.
  ElementColors own_colors(int block, const std::vector<int>& elements) const;
  /// Fills the element load vectors f (and, when K != null, matrices Ke) of a chunk of
  /// elements: each element's values one after the other, dofs_per_element() each.
  using ElementLoadKernel =
      std::function<void(std::span<const int> elements, double* f, double* Ke)>;
  /// Adds the element loads of `colors` in block `block` to F and, when K != null,
  /// subtracts their matrices from K (r = f_int − f_ext). F is this process's share: see
  /// sum_shares.
  void add_element_loads(int block, const ElementColors& colors, const ElementLoadKernel& kernel,
                         NodePositions& F, SparseMatrix* K) const;
  /// Whether per-node vectors of element loads must be summed at the shared nodes
  /// (several processes, no LocalShare alive).
  bool sums_shares() const { return shared(); }
  /// Sums a per-node vector at the shared nodes when sums_shares().
  void sum_shares(NodePositions& F) const { reduce(F); }

  /// Consistent mass (values overwritten) and lumped nodal masses (row sum; HRZ for tri6 and
  /// quad8, whose row sums are not all positive), point masses included in both.
  void mass(SparseMatrix* M, VecX* lumped) const;  ///< either may be null
  /// K += scale T, T the geometric stiffness of a uniform unit tension in every membrane and
  /// cable (ElementBlock::tension_stiffness: symmetric, constant), K on this assembler's
  /// pattern. Added element by element: no matrix of T is made.
  void add_tension_stiffness(SparseMatrix& K, double scale) const;
  /// T's diagonal, one entry per equation (this process's share on several processes).
  VecX tension_stiffness_diagonal() const;
  /// Nodal forces of gravity g: consistent mass times g (point masses included), summed at
  /// the shared nodes.
  NodePositions gravity_forces(const Vec3& g) const;

  int num_colors(int block) const { return static_cast<int>(colors_[block].size()); }
  /// Elements this process computes (all of them on one process).
  long own_elements() const;
  /// Nodes held by elements of more than one process (the partition's cut; 0 on one process).
  long shared_nodes() const { return piece_ ? piece_->element_cut : 0; }
  /// The processes this one exchanges shared nodes with (0 on one process).
  long neighbours() const { return piece_ ? static_cast<long>(piece_->neighbours.size()) : 0; }
  /// The partition used (kRows when PT-Scotch was asked for but is not available; see
  /// partition_note()).
  ElementPartition partition() const {
    return piece_ ? piece_->partition : ElementPartition::kRows;
  }
  /// Why the partition asked for was not used (empty when it was).
  const std::string& partition_note() const;
  /// The elements of block `block` this process computes, ascending.
  const std::vector<int>& own(int block) const { return own_[static_cast<size_t>(block)]; }
  /// Per block, the elements this process computes (every element on one process).
  const std::vector<std::vector<int>>& own_by_block() const { return own_; }

  /// Whether element e of block `block` is one this process computes.
  bool owns(int block, int e) const { return local_[static_cast<size_t>(block)][e] >= 0; }
  /// Whether this process adds node n's nodal terms (point loads, point masses' drag, the
  /// whole-model vectors of gravity and edge loads) to its share of a sum over the processes:
  /// the lowest process whose elements hold n, or the first when no element does. Every
  /// node on one process.
  /// n < 0 (a node this process does not hold): false.
  bool keeps_node(int n) const {
    return n >= 0 && (!piece_ || piece_->kept[static_cast<size_t>(n)] != 0);
  }
  /// Nodes of the whole model (the piece's nodes are model.num_nodes()).
  int global_nodes() const { return piece_ ? piece_->global_nodes : model_.num_nodes(); }
  /// Keeps node n's column of P only where keeps_node(n) (zero elsewhere); nothing on one
  /// process.
  void keep_kept_nodes(NodePositions& P) const;
  /// Each node's column of a per-node array as the process keeping it holds it, at every
  /// node this process holds (keep_kept_nodes, then summed at the shared nodes). A collective
  /// call; nothing on one process.
  void from_keepers(NodePositions& P) const;
  /// A per-node array in the whole model's node order on the first process (each node from
  /// its keeper; empty on the others): what a checkpoint writes. P itself on one process. A
  /// collective call.
  NodePositions gather_nodes(const NodePositions& P) const;
  /// The piece's columns of a whole-model per-node array (the inverse of gather_nodes, on
  /// every process); `whole` itself on one process.
  NodePositions piece_of(const NodePositions& whole) const;
  /// Completes per-node partial sums at the shared nodes (those more than one process holds):
  /// each array holds `per_node` consecutive values per node of the piece (a 3 x nodes
  /// NodePositions: 3), this process's share; on return the shared nodes' entries hold the
  /// sum over the processes holding the node, added in rank order (the same bits on every
  /// process), the other entries are untouched. Point to point with the neighbouring
  /// processes only: one message each way per neighbour, of the nodes both hold. Called on
  /// every process alike; nothing on one process.
  void sum_at_shared_nodes(std::span<const std::pair<double*, int>> arrays) const;
  /// The same for one per-node array.
  void sum_at_shared_nodes(NodePositions& P) const {
    const std::pair<double*, int> parts[] = {{P.data(), 3}};
    sum_at_shared_nodes(parts);
  }

  /// While alive, the vector results of internal and of the element loads are this
  /// process's share (its own elements; the nodal terms a caller adds belong to the nodes it
  /// keeps_node), not summed over the processes: what the output completes itself at the
  /// shared nodes only. A gas volume stays summed (collective). No matrix then.
  class LocalShare {
   public:
    explicit LocalShare(const Assembler& a) : a_(a), was_(a.share_only_) { a.share_only_ = true; }
    ~LocalShare() { a_.share_only_ = was_; }
    LocalShare(const LocalShare&) = delete;
    LocalShare& operator=(const LocalShare&) = delete;

   private:
    const Assembler& a_;
    bool was_;
  };
  /// Whether a LocalShare is alive on several processes (nodal terms: keeps_node only).
  bool local_share() const { return piece_ && share_only_; }

 private:
  struct Colored {
    std::vector<std::vector<int>> colors;  // element lists
  };
  /// Adds the element vectors of the listed colours to F and matrix_sign times their matrices
  /// to K (when tangent). `compute(elements, r, K, f, Kp)` fills r and K, and when it returns
  /// true load vectors f of the same elements too (in the same pass): added to Fload, their
  /// matrices Kp (a load stiffness) subtracted from K.
  template <class Compute>
  void run(int block, const std::vector<std::vector<int>>& colors, const Compute& compute,
           bool tangent, NodePositions& F, NodePositions* Fload, SparseMatrix* K,
           double matrix_sign) const;

  struct ElementBuffers {
    std::vector<double> r, r_load;
    // Aligned: blocks write element matrices through fixed-size Eigen references into it.
    std::vector<double, Eigen::aligned_allocator<double>> K, K_load;
  };

  using Colors = std::vector<std::vector<int>>;
  // The pattern (elements and couplings_), its diagonal positions and the blocks' scatter
  // positions.
  void build_positions();
  // Sums a per-node vector at the shared nodes (nothing on one process or for a local share).
  void reduce(NodePositions& F) const;
  bool shared() const { return piece_ && !share_only_; }
  // A point mass is added once, by the first process (its share holds their nodes' blocks).
  bool adds_point_masses() const;
  // Adds Me ⊗ I3 (Me: the scalar node matrix of block bi's k-th own element) into M.
  void add_node_matrix(size_t bi, size_t k, const MatX& Me, SparseMatrix& M) const;

  const Model& model_;
  const DofMap& dofs_;
  int neq_ = 0;
  Eigen::Index nonzeros_ = 0;
  const ModelPiece* piece_ = nullptr;    // the model's piece (several processes), or null
  mutable bool share_only_ = false;      // a LocalShare is alive
  std::vector<std::vector<int>> own_;    // per block: this process's elements, ascending
  std::vector<std::vector<int>> local_;  // per block: element -> index into own_ (-1: not)
  std::vector<int> diagonal_at_;         // see diagonal_positions()
  std::vector<int> lone_nodes_;          // own diagonal blocks, no own element: Assembler()
  std::vector<Colors> colors_;           // per block: own elements
  std::vector<ElementScatter> scatter_;  // per block: its own elements' positions
  mutable SparseMatrix first_matrix_;    // the pattern built for scatter_, given to the first
                                         // make_matrix (later ones build it again)
  // set_couplings, sorted (i < j), and pattern_revision().
  std::vector<std::array<int, 2>> couplings_;
  long revision_ = 0;
  int max_dofs_ = 0;
  mutable std::vector<ElementBuffers> buffers_;  // one per thread, reused across calls
  // sum_at_shared_nodes: this process's values at its shared nodes, what goes to and comes
  // from each neighbour, the sums; reused across calls.
  mutable std::vector<double> shared_own_, shared_out_, shared_in_;
  mutable std::vector<processes::Channel> shared_channels_;
};

}  // namespace velum
