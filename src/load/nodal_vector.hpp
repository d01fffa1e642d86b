// Adding c times a constant per-node vector (edge loads, gravity) to the external forces: on
// a process's share, at the nodes it keeps only.
#pragma once

#include "velum/assembly/assembler.hpp"

namespace velum {

inline void add_nodal_vector(const Assembler& a, double c, const NodePositions& F,
                             NodePositions& out) {
  if (!a.local_share()) {
    out += c * F;
    return;
  }
  for (Eigen::Index n = 0; n < out.cols(); ++n)
    if (a.keeps_node(static_cast<int>(n))) out.col(n) += c * F.col(n);
}

}  // namespace velum
