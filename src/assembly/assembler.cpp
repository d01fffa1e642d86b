#include "velum/assembly/assembler.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <numeric>

#include "element_colors.hpp"
#include "velum/math/threads.hpp"
#include "velum/parallel/model_piece.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {
namespace {

constexpr int kChunk = 16;             // elements per kernel call, and the colouring's groups
constexpr int kMinParallelChunks = 8;  // chunks per colour worth a parallel region
constexpr int kParallelPatternNodes = 20000;  // nodes worth building the pattern on all threads

// Rotates the rows/cols of framed nodes into their local frames (in place).
void to_local_frames(const DofMap& dofs, std::span<const int> nodes, double* r, double* K,
                     int ndof) {
  for (size_t i = 0; i < nodes.size(); ++i) {
    const int f = dofs.frame(nodes[i]);
    if (f < 0) continue;
    const Mat3& R = dofs.rotation(f);
    Eigen::Map<Vec3> ri(r + 3 * i);
    ri = R * ri;
    if (K) {
      Eigen::Map<MatX> Km(K, ndof, ndof);
      Km.middleRows(3 * i, 3) = R * Km.middleRows(3 * i, 3);
      Km.middleCols(3 * i, 3) = Km.middleCols(3 * i, 3) * R.transpose();
    }
  }
}

// The matrix pattern in compressed columns: equations i and j are coupled when their nodes
// share an element (every component with every component: frames mix them), and every node
// with equations is coupled with itself (its elements; `lone_nodes` for point masses and
// nodes of no element: a diagonal for every equation). Built
// from node adjacency, it costs a few bytes per node pair instead of a triplet per
// element-matrix entry (117 MB for 50k quad4), and is cheap enough to rebuild on demand
// rather than kept next to the matrices built on it.
//
// On several processes, the pattern of this process's share: the couplings of its own
// elements (`own`, per block), the self-coupling of their nodes and of `lone_nodes` (on the
// first process: the point masses' nodes, where masses and payload drag are added, and the
// nodes of no element).
//
// `couplings`: node pairs coupled beyond the elements (a contact's node and its face's nodes,
// Assembler::set_couplings), both ways; pairs with a node this process does not hold are left
// out.
void build_pattern(const Model& model, const DofMap& dofs, const std::vector<std::vector<int>>& own,
                   const std::vector<int>& lone_nodes,
                   const std::vector<std::array<int, 2>>& couplings, SparseMatrix& A) {
  const int nn = model.num_nodes(), neq = dofs.num_equations();
  std::vector<char> touched(nn, 0);
  for (size_t bi = 0; bi < model.blocks.size(); ++bi)
    for (int e : own[bi])
      for (int a : model.blocks[bi]->nodes(e)) touched[a] = 1;
  for (int n : lone_nodes) touched[n] = 1;
  // Node adjacency with repeats: count, then fill.
  std::vector<int> start(nn + 1, 0), end(nn), adj, fill;
  auto visit = [&](const auto& link) {
    for (int n = 0; n < nn; ++n)
      if (touched[n]) link(n, n);
    for (size_t bi = 0; bi < model.blocks.size(); ++bi)
      for (int e : own[bi])
        for (int a : model.blocks[bi]->nodes(e))
          for (int c : model.blocks[bi]->nodes(e))
            if (a != c) link(a, c);
    for (const auto& [a, c] : couplings)
      if (a != c && a >= 0 && c >= 0 && a < nn && c < nn && touched[a] && touched[c])
        link(a, c), link(c, a);
  };
  visit([&](int a, int) { ++start[a + 1]; });
  for (int n = 0; n < nn; ++n) start[n + 1] += start[n];
  adj.resize(start[nn]);
  fill.assign(start.begin(), start.end() - 1);
  visit([&](int a, int b) { adj[fill[a]++] = b; });
  // Each node's list sorted, without repeats (its end moves down), and the length of the
  // columns of its equations: the equations of its adjacent nodes.
  std::vector<int> length(nn, 0);
  const bool parallel = nn > kParallelPatternNodes;
#pragma omp parallel for schedule(dynamic, 256) if (parallel)
  for (int n = 0; n < nn; ++n) {
    const auto first = adj.begin() + start[n], last = adj.begin() + start[n + 1];
    std::sort(first, last);
    end[n] = static_cast<int>(std::unique(first, last) - adj.begin());
    for (int k = start[n]; k < end[n]; ++k)
      for (int c = 0; c < 3; ++c) length[n] += dofs.equation(adj[k], c) >= 0;
  }
  // Sized exactly before it is filled (grown entry by entry, the copies and first touches of
  // its reallocations were most of the time here).
  std::vector<int> node_of(neq, -1);
  for (int n = 0; n < nn; ++n)
    for (int c = 0; c < 3; ++c)
      if (const int q = dofs.equation(n, c); q >= 0 && touched[n]) node_of[q] = n;
  A.resize(neq, neq);
  int* outer = A.outerIndexPtr();
  outer[0] = 0;
  for (int q = 0; q < neq; ++q)
    outer[q + 1] = outer[q] + (node_of[q] >= 0 ? length[node_of[q]] : 0);
  A.resizeNonZeros(outer[neq]);
  int* inner = A.innerIndexPtr();
  // A node's column, built once (sorted) and copied to each of its equations.
#pragma omp parallel if (parallel)
  {
    std::vector<int> column;
#pragma omp for schedule(dynamic, 256)
    for (int n = 0; n < nn; ++n) {
      if (length[n] == 0) continue;
      column.clear();
      for (int k = start[n]; k < end[n]; ++k)
        for (int c = 0; c < 3; ++c)
          if (const int i = dofs.equation(adj[k], c); i >= 0) column.push_back(i);
      std::sort(column.begin(), column.end());
      for (int c = 0; c < 3; ++c)
        if (const int q = dofs.equation(n, c); q >= 0)
          std::copy(column.begin(), column.end(), inner + outer[q]);
    }
  }
}

}  // namespace

Assembler::Assembler(const Model& model, const DofMap& dofs) : model_(model), dofs_(dofs) {
  neq_ = dofs.num_equations();
  if ((piece_ = model.piece.get())) {  // shared out by share_model
    own_ = piece_->own;
    lone_nodes_ = piece_->lone;
  } else {
    for (const auto& bp : model.blocks) {
      auto& own = own_.emplace_back(static_cast<size_t>(bp->size()));
      std::iota(own.begin(), own.end(), 0);
    }
    // The nodes in no element and the point masses' nodes: their diagonal blocks.
    std::vector<char> in_element(static_cast<size_t>(model.num_nodes()), 0);
    for (const auto& bp : model.blocks)
      for (int n : bp->connectivity()) in_element[static_cast<size_t>(n)] = 1;
    for (size_t n = 0; n < in_element.size(); ++n)
      if (!in_element[n]) lone_nodes_.push_back(static_cast<int>(n));
    for (const auto& pm : model.masses) lone_nodes_.push_back(pm.node);
  }
  for (size_t b = 0; b < own_.size(); ++b) {
    auto& local = local_.emplace_back(model.blocks[b]->size(), -1);
    for (size_t i = 0; i < own_[b].size(); ++i) local[own_[b][i]] = static_cast<int>(i);
  }
  for (size_t bi = 0; bi < model.blocks.size(); ++bi)
    colors_.push_back(color_element_groups(*model.blocks[bi], own_[bi], model.num_nodes(), kChunk));
  build_positions();
  for (const auto& b : model.blocks) max_dofs_ = std::max(max_dofs_, b->dofs_per_element());
}

void Assembler::build_positions() {
  build_pattern(model_, dofs_, own_, lone_nodes_, couplings_, first_matrix_);
  nonzeros_ = first_matrix_.nonZeros();
  diagonal_at_.assign(static_cast<size_t>(first_matrix_.outerSize()), -1);
  for (int j = 0; j < first_matrix_.outerSize(); ++j)
    for (int k = first_matrix_.outerIndexPtr()[j]; k < first_matrix_.outerIndexPtr()[j + 1]; ++k)
      if (first_matrix_.innerIndexPtr()[k] == j) diagonal_at_[static_cast<size_t>(j)] = k;
  scatter_.clear();
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi)
    scatter_.emplace_back(*model_.blocks[bi], own_[bi], dofs_, first_matrix_);
}

void Assembler::set_couplings(std::vector<std::array<int, 2>> pairs) {
  for (auto& p : pairs)
    if (p[0] > p[1]) std::swap(p[0], p[1]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (pairs == couplings_) return;
  couplings_ = std::move(pairs);
  build_positions();
  // A number no other pattern of any assembler had: a solver keyed on it analyses anew.
  static std::atomic<long> revisions{0};
  revision_ = ++revisions;
}

long Assembler::own_elements() const {
  long n = 0;
  for (const auto& own : own_) n += static_cast<long>(own.size());
  return n;
}

const std::string& Assembler::partition_note() const {
  static const std::string none;
  return piece_ ? piece_->partition_note : none;
}

bool Assembler::adds_point_masses() const {
  return !piece_ || processes::rank() == 0;
}

void Assembler::reduce(NodePositions& F) const {
  if (shared()) sum_at_shared_nodes(F);
}

void Assembler::keep_kept_nodes(NodePositions& P) const {
  if (!piece_) return;
  for (Eigen::Index n = 0; n < P.cols(); ++n)
    if (!piece_->kept[static_cast<size_t>(n)]) P.col(n).setZero();
}

void Assembler::from_keepers(NodePositions& P) const {
  if (!piece_) return;
  keep_kept_nodes(P);
  sum_at_shared_nodes(P);
}

NodePositions Assembler::gather_nodes(const NodePositions& P) const {
  if (!piece_) return P;
  // Each process sends its kept nodes' columns with their global index (every node is kept
  // by exactly one process); the first puts them in place.
  const ModelPiece& piece = *piece_;
  std::vector<double> mine;
  for (Eigen::Index n = 0; n < P.cols(); ++n)
    if (piece.kept[static_cast<size_t>(n)])
      mine.insert(mine.end(), {static_cast<double>(piece.global_node[static_cast<size_t>(n)]),
                               P(0, n), P(1, n), P(2, n)});
  const std::vector<double> all = processes::gather(mine);
  NodePositions whole;
  if (processes::rank() != 0) return whole;
  whole.setZero(3, piece.global_nodes);
  for (size_t k = 0; k + 3 < all.size(); k += 4)
    whole.col(static_cast<Eigen::Index>(all[k])) = Vec3(all[k + 1], all[k + 2], all[k + 3]);
  return whole;
}

NodePositions Assembler::piece_of(const NodePositions& whole) const {
  if (!piece_) return whole;
  const ModelPiece& piece = *piece_;
  NodePositions P(3, static_cast<Eigen::Index>(piece.global_node.size()));
  for (size_t n = 0; n < piece.global_node.size(); ++n)
    P.col(static_cast<Eigen::Index>(n)) = whole.col(piece.global_node[n]);
  return P;
}

void Assembler::sum_at_shared_nodes(std::span<const std::pair<double*, int>> arrays) const {
  if (!piece_) return;
  const ModelPiece& piece = *piece_;
  const std::vector<int>& shared = piece.shared;
  size_t m = 0;  // values per node, over the arrays
  for (const auto& a : arrays) m += static_cast<size_t>(a.second);
  // This process's values, node by node (each node's arrays' values together).
  shared_own_.resize(m * shared.size());
  for (size_t s = 0; s < shared.size(); ++s) {
    double* to = shared_own_.data() + s * m;
    const auto n = static_cast<size_t>(shared[s]);
    for (const auto& [data, k] : arrays) {
      const auto per = static_cast<size_t>(k);
      to = std::copy(data + n * per, data + (n + 1) * per, to);
    }
  }
  // One message each way per neighbour: the nodes both hold, in global order on both.
  shared_channels_.clear();
  size_t total = 0;
  for (size_t q = 0; q < piece.neighbours.size(); ++q) {
    const size_t count = piece.shared_with[q].size() * m;
    shared_channels_.push_back(
        {piece.neighbours[q], static_cast<int>(total), static_cast<int>(count)});
    total += count;
  }
  shared_out_.resize(total);
  shared_in_.resize(total);
  double* out = shared_out_.data();
  for (const auto& with : piece.shared_with)
    for (int s : with) out = std::copy_n(shared_own_.data() + static_cast<size_t>(s) * m, m, out);
  processes::exchange(shared_out_.data(), shared_channels_, shared_in_.data(), shared_channels_);
  // Sums in rank order of the processes holding each node, from zero: every holder adds the
  // same values in the same order, so all hold the same bits.
  const int rank = processes::rank();
  std::vector<double>& sum = shared_out_;  // sent: reused for the sums
  sum.assign(m * shared.size(), 0.0);
  auto add_own = [&] {
    for (size_t i = 0; i < m * shared.size(); ++i) sum[i] += shared_own_[i];
  };
  bool own_added = false;
  for (size_t q = 0; q < piece.neighbours.size(); ++q) {
    if (!own_added && piece.neighbours[q] > rank) add_own(), own_added = true;
    const double* from = shared_in_.data() + shared_channels_[q].at;
    for (int s : piece.shared_with[q]) {
      double* to = sum.data() + static_cast<size_t>(s) * m;
      for (size_t i = 0; i < m; ++i) to[i] += from[i];
      from += m;
    }
  }
  if (!own_added) add_own();
  for (size_t s = 0; s < shared.size(); ++s) {
    const double* from = sum.data() + s * m;
    const auto n = static_cast<size_t>(shared[s]);
    for (const auto& [data, k] : arrays) {
      const auto per = static_cast<size_t>(k);
      std::copy(from, from + per, data + n * per);
      from += per;
    }
  }
}

void combine_values(SparseMatrix& A, double a, const SparseMatrix* B, double b) {
  double* av = A.valuePtr();
  const Eigen::Index n = A.nonZeros();
  const double* bv = B ? B->valuePtr() : nullptr;
  const bool worth = n > kParallelMatrixEntries;
  if (bv && a != 0) {
    parallel_for(n, worth, [&](Eigen::Index i) { av[i] = a * av[i] + b * bv[i]; });
  } else if (bv) {
    parallel_for(n, worth, [&](Eigen::Index i) { av[i] = b * bv[i]; });
  } else if (a != 0) {
    parallel_for(n, worth, [&](Eigen::Index i) { av[i] *= a; });
  } else {
    parallel_for(n, worth, [&](Eigen::Index i) { av[i] = 0.0; });
  }
}

SparseMatrix Assembler::make_matrix() const {
  SparseMatrix A;
  make_matrix(A);
  return A;
}

void Assembler::make_matrix(SparseMatrix& A) const {
  if (first_matrix_.nonZeros() > 0) {
    A.swap(first_matrix_);
    first_matrix_ = SparseMatrix();  // A's old storage, if any
  } else {
    build_pattern(model_, dofs_, own_, lone_nodes_, couplings_, A);
  }
  double* values = A.valuePtr();
  const Eigen::Index n = nonzeros();
  parallel_for(n, n > kParallelMatrixEntries, [&](Eigen::Index i) { values[i] = 0.0; });
}

template <class Compute>
void Assembler::run(int bi, const std::vector<std::vector<int>>& colors, const Compute& compute,
                    bool tangent, NodePositions& F, NodePositions* Fload, SparseMatrix* K,
                    double matrix_sign) const {
  const auto& b = *model_.blocks[bi];
  // Element buffers per thread, sized for the largest element once and reused by every call.
  const int threads = omp_get_max_threads();
  if (static_cast<int>(buffers_.size()) < threads) {
    buffers_.resize(threads);
    for (auto& buf : buffers_) {
      buf.r.resize(static_cast<size_t>(kChunk) * max_dofs_);
      buf.r_load.resize(buf.r.size());
      buf.K.resize(static_cast<size_t>(kChunk) * max_dofs_ * max_dofs_);
      buf.K_load.resize(buf.K.size());
    }
  }
  const int nd = b.dofs_per_element();
  const ElementScatter& scatter = scatter_[bi];
  const int* local = local_[bi].data();
  double* values = K ? K->valuePtr() : nullptr;
  for (const auto& list : colors) {
    const int nchunks = (static_cast<int>(list.size()) + kChunk - 1) / kChunk;
    // A parallel region costs a fork and a barrier (and spin-waiting threads on a loaded
    // machine): below a few thousand element-dofs² of work per colour it costs more than it
    // saves, so small colours run on the calling thread; so does every colour on one thread
    // (libgomp enters even a one-thread region through the kernel).
    parallel_region(nchunks >= kMinParallelChunks, [&] {
      ElementBuffers& buf = buffers_[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (int c = 0; c < nchunks; ++c) {
        const int first = c * kChunk;
        const int count = std::min<int>(kChunk, static_cast<int>(list.size()) - first);
        std::span<const int> elems(list.data() + first, count);
        const bool loaded = compute(elems, buf.r.data(), tangent ? buf.K.data() : nullptr,
                                    buf.r_load.data(), tangent ? buf.K_load.data() : nullptr);
        for (int k = 0; k < count; ++k) {
          const int e = elems[k];
          const auto nodes = b.nodes(e);
          double* re = buf.r.data() + static_cast<size_t>(k) * nd;
          for (size_t i = 0; i < nodes.size(); ++i)
            for (int d = 0; d < 3; ++d) F(d, nodes[i]) += re[3 * i + d];
          if (loaded) {
            const double* fe = buf.r_load.data() + static_cast<size_t>(k) * nd;
            for (size_t i = 0; i < nodes.size(); ++i)
              for (int d = 0; d < 3; ++d) (*Fload)(d, nodes[i]) += fe[3 * i + d];
          }
          if (!tangent) continue;
          double* ke = buf.K.data() + static_cast<size_t>(k) * nd * nd;
          if (loaded) {
            const double* kl = buf.K_load.data() + static_cast<size_t>(k) * nd * nd;
            for (int q = 0; q < nd * nd; ++q) ke[q] = matrix_sign * ke[q] - kl[q];
          } else if (matrix_sign != 1.0) {
            for (int q = 0; q < nd * nd; ++q) ke[q] *= matrix_sign;
          }
          if (dofs_.has_frames()) to_local_frames(dofs_, nodes, re, ke, nd);
          scatter.add(local[e], ke, values);
        }
      }
    });
  }
}

void Assembler::internal(const NodePositions& x, NodePositions& F, SparseMatrix* K) const {
  NodePositions unused;
  internal(x, F, K, {}, unused);
}

void Assembler::internal(const NodePositions& x, NodePositions& F, SparseMatrix* K,
                         std::span<const double> block_pressure, NodePositions& Fp) const {
  F.setZero(3, model_.num_nodes());
  if (!block_pressure.empty()) Fp.setZero(3, model_.num_nodes());
  if (K) combine_values(*K, 0.0, nullptr, 0.0);
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi) {
    const auto& b = *model_.blocks[bi];
    const double p = bi < block_pressure.size() ? block_pressure[bi] : 0.0;
    run(
        static_cast<int>(bi), colors_[bi],
        [&](std::span<const int> elems, double* r, double* Ke, double* f, double* Kp) {
          if (p == 0) {
            b.internal(elems, x, r, Ke);
            return false;
          }
          b.surface()->internal_and_pressure(elems, x, p, r, Ke, f, Kp);
          return true;
        },
        K != nullptr, F, &Fp, K, 1.0);
  }
  reduce(F);
  if (!block_pressure.empty()) reduce(Fp);
}

void Assembler::explicit_forces(const NodePositions& x, NodePositions& F,
                                std::span<const double> block_pressure, NodePositions& Fp) const {
  // F and Fp zeroed in the first block's parallel region (each thread its share of the
  // nodes, before the barrier that ends the zeroing loop), or on the calling thread.
  const bool pressures = !block_pressure.empty();
  F.resize(3, model_.num_nodes());
  if (pressures) Fp.resize(3, model_.num_nodes());
  bool zeroed = false;
  const long entries = 3L * model_.num_nodes();
  const long zero_blocks = (entries + kVectorBlock - 1) / kVectorBlock;
  auto zero = [&](long z) {
    const long first = z * kVectorBlock, count = std::min(entries, first + kVectorBlock) - first;
    std::fill_n(F.data() + first, count, 0.0);
    if (pressures) std::fill_n(Fp.data() + first, count, 0.0);
  };
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi) {
    const auto& b = *model_.blocks[bi];
    const double p = bi < block_pressure.size() ? block_pressure[bi] : 0.0;
    if (!zeroed && !b.surface()) {
      for (long z = 0; z < zero_blocks; ++z) zero(z);
      zeroed = true;
    }
    if (const SurfaceBlock* surface = b.surface()) {
      // Each element's forces straight into F and Fp (no element-vector buffer): the chunks
      // of a colour share no node, and every node receives its terms in the same order
      // whatever the thread count.
      const Colors& colors = colors_[bi];
      size_t chunks = 0;
      for (const auto& list : colors) chunks += (list.size() + kChunk - 1) / kChunk;
      // One parallel region for all the colours (a barrier between them, no fork).
      parallel_region(chunks >= static_cast<size_t>(kMinParallelChunks) * colors.size(), [&] {
        if (!zeroed) {
#pragma omp for schedule(static)
          for (long z = 0; z < zero_blocks; ++z) zero(z);
        }
        for (const auto& list : colors) {
          const int nchunks = (static_cast<int>(list.size()) + kChunk - 1) / kChunk;
#pragma omp for schedule(static)
          for (int c = 0; c < nchunks; ++c) {
            const int first = c * kChunk;
            const int count = std::min<int>(kChunk, static_cast<int>(list.size()) - first);
            surface->explicit_forces(std::span<const int>(list.data() + first, count), x, p, F, Fp);
          }
        }
      });
      zeroed = true;
    } else {
      run(
          static_cast<int>(bi), colors_[bi],
          [&](std::span<const int> elems, double* r, double* Ke, double*, double*) {
            b.internal(elems, x, r, Ke);
            return false;
          },
          false, F, nullptr, nullptr, 1.0);
    }
  }
  if (!zeroed)  // no block
    for (long z = 0; z < zero_blocks; ++z) zero(z);
  reduce(F);
  if (pressures) reduce(Fp);
}

void Assembler::pressure(int i, double p, const NodePositions& x, NodePositions& Fext,
                         SparseMatrix* K) const {
  // The load at a constant p: its parameters with the value p, bound to this assembler.
  for (const auto& load : model_.loads)
    if (dynamic_cast<const PressureLoad*>(load.get()) && i-- == 0) {
      std::unique_ptr<Load> at_p = load->clone();
      auto& params = dynamic_cast<PressureLoad&>(*at_p);
      params.value = p;
      params.function = -1;
      const NodePositions none;
      const LoadState s{.t = 0, .x = x, .V = none};
      LoadOutput out{.F = Fext, .K = K};
      at_p->bind({model_, *this, dofs_})->add(s, out);
      return;
    }
}

Assembler::ElementColors Assembler::own_colors(int block, const std::vector<int>& elements) const {
  std::vector<int> kept;
  for (int e : elements)
    if (local_[block][e] >= 0) kept.push_back(e);
  return color_element_groups(*model_.blocks[block], kept, model_.num_nodes(), kChunk);
}

void Assembler::add_element_loads(int block, const ElementColors& colors,
                                  const ElementLoadKernel& kernel, NodePositions& F,
                                  SparseMatrix* K) const {
  // The loads enter the residual r = f_int − f_ext negated: run subtracts their matrices.
  run(
      block, colors,
      [&](std::span<const int> elems, double* f, double* Ke, double*, double*) {
        kernel(elems, f, Ke);
        return false;
      },
      K != nullptr, F, nullptr, K, -1.0);
}

void Assembler::mass(SparseMatrix* M, VecX* lumped) const {
  if (M) std::fill(M->valuePtr(), M->valuePtr() + M->nonZeros(), 0.0);
  if (lumped) lumped->setZero(model_.num_nodes());
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi) {
    const auto& b = *model_.blocks[bi];
    const int nn = b.nodes_per_element();
    MatX Me(nn, nn);
    VecX share(nn);
    for (size_t k = 0; k < own_[bi].size(); ++k) {
      const int e = own_[bi][k];
      b.mass(e, Me.data());
      const auto nodes = b.nodes(e);
      if (M) add_node_matrix(bi, k, Me, *M);
      if (!lumped) continue;
      b.shape().lump(Me.data(), share.data());
      for (int i = 0; i < nn; ++i) (*lumped)[nodes[i]] += share[i];
    }
  }
  // The point masses once, then the shares summed where processes share nodes.
  if (adds_point_masses())
    for (const auto& pm : model_.masses) {
      if (M)
        for (int d = 0; d < 3; ++d)
          if (const int a = dofs_.equation(pm.node, d); a >= 0) M->coeffRef(a, a) += pm.mass;
      if (lumped) (*lumped)[pm.node] += pm.mass;
    }
  if (lumped && piece_) {
    const std::pair<double*, int> parts[] = {{lumped->data(), 1}};
    sum_at_shared_nodes(parts);
  }
}

namespace {

// fn(block, k, element, Ke) with Ke the node matrix of element own[block][k]'s unit tension
// (ElementBlock::tension_stiffness).
template <class Fn>
void for_each_tension_stiffness(const Model& model, const std::vector<std::vector<int>>& own,
                                Fn&& fn) {
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = *model.blocks[bi];
    MatX Ke(b.nodes_per_element(), b.nodes_per_element());
    for (size_t k = 0; k < own[bi].size(); ++k) {
      b.tension_stiffness(own[bi][k], Ke.data());
      fn(bi, k, own[bi][k], Ke);
    }
  }
}

}  // namespace

void Assembler::add_tension_stiffness(SparseMatrix& K, double scale) const {
  for_each_tension_stiffness(model_, own_, [&](size_t bi, size_t k, int, MatX& Ke) {
    Ke *= scale;
    add_node_matrix(bi, k, Ke, K);
  });
}

VecX Assembler::tension_stiffness_diagonal() const {
  // A node matrix (Ke(i, j) I₃, frames leave it so) puts Ke(i, i) on node i's three diagonal
  // entries.
  VecX d = VecX::Zero(dofs_.num_equations());
  for_each_tension_stiffness(model_, own_, [&](size_t bi, size_t, int e, const MatX& Ke) {
    const auto nodes = model_.blocks[bi]->nodes(e);
    for (int i = 0; i < Ke.rows(); ++i)
      for (int c = 0; c < 3; ++c)
        if (const int q = dofs_.equation(nodes[i], c); q >= 0) d[q] += Ke(i, i);
  });
  return d;
}

void Assembler::add_node_matrix(size_t bi, size_t k, const MatX& Me, SparseMatrix& M) const {
  const ElementScatter& scatter = scatter_[bi];
  const int nn = static_cast<int>(Me.rows());
  for (int j = 0; j < nn; ++j)
    for (int i = 0; i < nn; ++i)
      for (int d = 0; d < 3; ++d) {  // frames leave R I Rᵀ = I unchanged
        const int q = scatter.position(static_cast<int>(k), 3 * i + d, 3 * j + d);
        if (q >= 0) M.valuePtr()[q] += Me(i, j);
      }
}

NodePositions Assembler::gravity_forces(const Vec3& g) const {
  NodePositions F = NodePositions::Zero(3, model_.num_nodes());
  for (size_t bi = 0; bi < model_.blocks.size(); ++bi) {
    const auto& b = *model_.blocks[bi];
    const int nn = b.nodes_per_element();
    MatX Me(nn, nn);
    for (int e : own_[bi]) {
      b.mass(e, Me.data());
      const auto nodes = b.nodes(e);
      for (int i = 0; i < nn; ++i) F.col(nodes[i]) += Me.row(i).sum() * g;
    }
  }
  if (adds_point_masses())
    for (const auto& pm : model_.masses) F.col(pm.node) += pm.mass * g;
  sum_at_shared_nodes(F);
  return F;
}

}  // namespace velum
