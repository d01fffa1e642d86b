#include "velum/assembly/dof_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "velum/math/threads.hpp"
#include "velum/parallel/model_piece.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {

DofMap::DofMap(const Model& model) {
  const int nn = model.num_nodes();
  std::vector<char> eliminated(3 * nn, 0);
  frame_of_.assign(nn, -1);
  for (const auto& f : model.fixed)
    for (int n : f.nodes)
      for (int c = 0; c < 3; ++c)
        if (f.fix[c]) eliminated[3 * n + c] = 1;
  for (const auto& p : model.prescribed)
    for (int n : p.nodes) eliminated[3 * n] = eliminated[3 * n + 1] = eliminated[3 * n + 2] = 1;
  for (const auto& s : model.symmetry) {
    const Vec3 nrm = s.normal.normalized();
    int axis = -1;
    for (int c = 0; c < 3; ++c)
      if (std::abs(std::abs(nrm[c]) - 1.0) < 1e-12) axis = c;
    for (int n : s.nodes) {
      if (axis >= 0 && frame_of_[n] < 0) {
        eliminated[3 * n + axis] = 1;
        continue;
      }
      // Skew plane (or a second plane on a node that already has a frame): local frame with
      // the normal as first axis. A node on two skew planes keeps only the line they share.
      if (frame_of_[n] < 0) {
        const Vec3 t1 =
            (std::abs(nrm.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(nrm).normalized();
        Mat3 R;
        R.row(0) = nrm;
        R.row(1) = t1;
        R.row(2) = nrm.cross(t1);
        frame_of_[n] = static_cast<int>(frames_.size());
        frames_.push_back(R);
        eliminated[3 * n] = 1;
      } else {
        // Second plane on a framed node: rebuild the frame as (n1, n2', line direction).
        Mat3& R = frames_[frame_of_[n]];
        const Vec3 n1 = R.row(0);
        const Vec3 dir = n1.cross(nrm);
        if (dir.norm() < 1e-12) continue;  // same plane twice
        const Vec3 d = dir.normalized();
        R.row(1) = d.cross(n1);
        R.row(2) = d;
        eliminated[3 * n + 1] = 1;
      }
    }
  }
  if (model.piece) {
    take_piece(*model.piece, eliminated);
    return;
  }
  eq_.assign(3 * nn, -1);
  for (int i = 0; i < 3 * nn; ++i)
    if (!eliminated[i]) eq_[i] = neq_++;
  for (int n = 0; n < nn; ++n) {
    const int k = (eq_[3 * n] >= 0) + (eq_[3 * n + 1] >= 0) + (eq_[3 * n + 2] >= 0);
    whole_nodes_ = whole_nodes_ && (k == 0 || k == 3);
  }
  layout_ = EquationLayout(neq_);
}

std::vector<long> DofMap::row_start() const {
  return row_start(processes::count());
}

std::vector<long> DofMap::row_start(int size) const {
  // Contiguous ranges, whole blocks of three when the equations come so, as even as PETSc's
  // own split (PetscSolver uses these).
  const int bs = whole_nodes_ && neq_ % 3 == 0 ? 3 : 1;
  std::vector<long> start(static_cast<size_t>(size) + 1);
  for (int r = 0; r <= size; ++r)
    start[static_cast<size_t>(r)] = processes::range_start(neq_, bs, size, r);
  return start;
}

void DofMap::take_piece(const ModelPiece& piece, const std::vector<char>& eliminated) {
  eq_ = piece.equation;
  neq_ = piece.global_equations;
  whole_nodes_ = piece.whole_nodes;
  for (size_t i = 0; i < eq_.size(); ++i)
    if ((eq_[i] < 0) != (eliminated[i] != 0))
      throw std::logic_error("a piece's constraints differ from the whole model's numbering");
  // Its local equations: the ones it owns (the row range), then the others' of its nodes.
  const std::vector<long> start = row_start();
  const auto rank = static_cast<size_t>(processes::rank());
  const long first = start[rank], last = start[rank + 1];
  std::vector<long> ghosts;
  for (int g : eq_)
    if (g >= 0 && (g < first || g >= last)) ghosts.push_back(g);
  std::sort(ghosts.begin(), ghosts.end());  // a node's equations are distinct: no repeats
  layout_ = EquationLayout(start, std::move(ghosts));
  local_.assign(eq_.size(), -1);
  for (size_t i = 0; i < eq_.size(); ++i)
    if (eq_[i] >= 0) local_[i] = layout_.local_of(eq_[i]);
}

void DofMap::scatter(const VecX& reduced, NodePositions& full) const {
  const int nn = num_nodes();
  const std::vector<int>& eq = local_.empty() ? eq_ : local_;
  if (frames_.empty()) {  // no node in a frame of its own: the components as they are
    double* x = full.data();
    const int* e = eq.data();
    for (long k = 0; k < 3L * nn; ++k)
      if (e[k] >= 0) x[k] = reduced[e[k]];
    return;
  }
  for (int n = 0; n < nn; ++n) {
    const int* e = eq.data() + 3 * n;
    if (e[0] < 0 && e[1] < 0 && e[2] < 0) continue;  // nothing to set
    Vec3 local = to_local(n, full.col(n));
    for (int c = 0; c < 3; ++c)
      if (e[c] >= 0) local[c] = reduced[e[c]];
    full.col(n) = to_global(n, local);
  }
}

void DofMap::keep_eliminated(NodePositions& full) const {
  for (int n = 0; n < num_nodes(); ++n) {
    Vec3 local = to_local(n, full.col(n));
    for (int c = 0; c < 3; ++c)
      if (eq_[3 * n + c] >= 0) local[c] = 0;
    full.col(n) = to_global(n, local);
  }
}

void DofMap::gather(const NodePositions& full, VecX& reduced) const {
  reduced.resize(num_equations());
  const int nn = num_nodes();
  const std::vector<int>& eq = local_.empty() ? eq_ : local_;
  if (frames_.empty()) {
    const double* x = full.data();
    const int* e = eq.data();
    for (long k = 0; k < 3L * nn; ++k)
      if (e[k] >= 0) reduced[e[k]] = x[k];
    return;
  }
  for (int n = 0; n < nn; ++n) {
    const Vec3 local = to_local(n, full.col(n));
    for (int c = 0; c < 3; ++c)
      if (eq[3 * n + c] >= 0) reduced[eq[3 * n + c]] = local[c];
  }
}

void DofMap::gather_difference(const NodePositions& a, const NodePositions& b,
                               VecX& reduced) const {
  if (!frames_.empty()) {
    gather(a - b, reduced);
    return;
  }
  reduced.resize(num_equations());
  const double* pa = a.data();
  const double* pb = b.data();
  const int* e = equations();
  parallel_ranges(3L * num_nodes(), [&](long first, long last) {
    for (long k = first; k < last; ++k)
      if (e[k] >= 0) reduced[e[k]] = pa[k] - pb[k];
  });
}

}  // namespace velum
