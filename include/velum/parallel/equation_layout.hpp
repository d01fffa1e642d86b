// Where a process's equations sit in the global numbering (docs/parallel.md). On several
// processes each holds its *local* equations: first those it owns (a contiguous range of the
// global numbering, the rows the PETSc matrix gives it), in global order, then its *ghosts*
// (equations another process owns that its elements or kept nodes touch), ascending global.
// A ghost holds its owner's value whenever a vector is handed on ("consistent"), so
// element-wise algebra needs nothing; reductions are over the owned entries only. On one
// process the layout is trivial: every equation owned, no ghosts, every call here is nothing
// or Eigen's own.
#pragma once

#include <vector>

#include "velum/math/types.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {

class EquationLayout {
 public:
  /// One process: `total` equations, all owned.
  explicit EquationLayout(int total = 0) : owned_(total), total_(total), row_start_{0, total} {}
  /// Several: this process owns [row_start[rank], row_start[rank + 1]) of the global
  /// numbering (row_start has count() + 1 entries); `ghosts` ascending, none owned here. A
  /// collective call (the processes tell each other which ghosts they read).
  EquationLayout(std::vector<long> row_start, std::vector<long> ghosts);

  bool distributed() const { return distributed_; }
  int owned() const { return owned_; }
  int local() const { return owned_ + static_cast<int>(ghosts_.size()); }
  long total() const { return total_; }
  /// The first global equation this process owns.
  long first() const { return first_; }
  /// Global equation of local equation i.
  long global(int i) const { return i < owned_ ? first_ + i : ghosts_[i - owned_]; }
  /// Local equation of global g, or -1 when this process holds no copy of it.
  int local_of(long g) const;
  /// The process that owns global equation g.
  int owner(long g) const;
  /// Where every process's owned range starts (count() + 1 entries; {0, total} on one).
  const std::vector<long>& row_start() const { return row_start_; }

  /// Sums over the owned entries, summed over the processes (the same bits everywhere).
  double dot(const VecX& a, const VecX& b) const;
  double norm(const VecX& a) const;
  /// Copies every owner's values into the ghosts that hold them (a collective call).
  void update_ghosts(VecX& x) const;
  /// Adds the ghosts' partial sums into their owners (each owner adds what the others send
  /// in rank order after its own), then update_ghosts: afterwards every process holds the
  /// total, consistent. A collective call.
  void sum_to_owners(VecX& x) const;
  /// The owned entries of every process, in global order, on the first process (empty on
  /// the others); on one process, x.
  VecX gather_global(const VecX& x) const;
  /// This process's local entries of a vector in global order that every process holds
  /// whole (a checkpoint read back); `whole` itself on one process.
  VecX local_part(const VecX& whole) const;

 private:
  bool distributed_ = false;
  int owned_ = 0;
  long first_ = 0, total_ = 0;
  std::vector<long> row_start_{0, 0};
  std::vector<long> ghosts_;
  // The forward exchange (owners to ghosts), built once: the owned entries sent to each
  // neighbouring process (one that reads a ghost of this one's equations), concatenated in
  // rank order, and the ghosts received from each owner, likewise; one channel per neighbour
  // and direction (processes::exchange, point to point). The reverse exchange is the same
  // pattern the other way.
  std::vector<int> send_, receive_;
  std::vector<processes::Channel> to_readers_, from_owners_;
  mutable std::vector<double> out_, in_;  // buffers, reused
};

}  // namespace velum
