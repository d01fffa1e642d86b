// The penetrations a contact finds at its start, for the sheet and rigid-body contact terms
// alike: counted, the deepest kept and, with a relaxation (relax_steps), each slot's depth an
// offset on its gap that shrinks to zero over the first accepted steps (docs/contact.md,
// "Initial penetrations"). Kept through checkpoints, so that a restart inside the relaxation
// goes on shrinking the same offsets.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/parallel/processes.hpp"

namespace velum::contact {

class InitialPenetrations {
 public:
  /// One offset per slot (a contact node, or a node's pass), none found yet.
  void resize(size_t slots) { offset_.assign(slots, 0.0); }
  /// Slot k's gap at the start: a penetration when negative. `counted`: false for a node
  /// another process keeps (it counts it), so that the sum over processes counts it once.
  void note(size_t k, double gap, int relax_steps, bool counted = true) {
    if (!(gap < 0)) return;
    if (counted) ++count_;
    depth_ = std::max(depth_, -gap);
    if (relax_steps > 0) offset_[k] = -gap;
  }
  /// What is left of slot k's offset during the accepted step steps + 1: shrinking linearly
  /// to zero over relax_steps steps; none without a relaxation.
  double relaxed(size_t k, int relax_steps) const {
    if (offset_[k] <= 0 || relax_steps <= 0) return 0.0;
    return offset_[k] * std::max(0.0, 1.0 - static_cast<double>(steps_ + 1) / relax_steps);
  }
  /// The count and the deepest made the whole model's, on every process (a collective call,
  /// once, after the last note): the account and the warning then need no reduction.
  void total_over_processes() {
    double count[1] = {static_cast<double>(count_)};
    processes::sum(count, 1);
    count_ = static_cast<int>(count[0]);
    depth_ = processes::max(depth_);
  }
  /// An accepted step.
  void commit() { ++steps_; }
  int count() const { return count_; }
  double depth() const { return depth_; }

  /// A warning naming `what` ("contact 0 with 'ball'") where any were found.
  void warn(const std::string& what, int relax_steps,
            const std::function<void(std::string)>& warn) const {
    if (count_ > 0)
      warn(fmt::format("{}: {} initial penetrations, the deepest {:.4g}{}", what, count_, depth_,
                       relax_steps > 0
                           ? fmt::format(" (relaxed over the first {} steps)", relax_steps)
                           : std::string(" (pushed out at the first step)")));
  }

  void save(std::vector<double>& out) const {
    out.push_back(steps_);
    out.push_back(count_);
    out.push_back(depth_);
    out.insert(out.end(), offset_.begin(), offset_.end());
  }
  size_t restore(const std::vector<double>& in, size_t at) {
    if (in.size() < at + 3 + offset_.size())
      throw std::invalid_argument("the contact's saved initial penetrations do not fit its nodes");
    steps_ = static_cast<int>(in[at++]);
    count_ = static_cast<int>(in[at++]);
    depth_ = in[at++];
    for (double& o : offset_) o = in[at++];
    return at;
  }

 private:
  std::vector<double> offset_;  // per slot: its initial depth (with a relaxation), else 0
  int steps_ = 0, count_ = 0;
  double depth_ = 0;
};

}  // namespace velum::contact
