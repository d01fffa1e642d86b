// The scale of the automatic contact penalties (docs/contact.md): the diagonal of an element's
// tangent at the reference, unconstrained. Unconstrained, because a node held in a plane keeps
// its sheet's stiffness: the apex of a bulge on two symmetry planes moves only along the
// sheet's normal, where a membrane is nearly without stiffness (1.4e3 N/m there against the
// 5e5 N/m of its neighbours in examples/airbag-impact). Private to src/load.
#pragma once

#include <Eigen/Core>

#include <span>
#include <vector>

#include "velum/model/element_block.hpp"

namespace velum {

class ReferenceDiagonal {
 public:
  /// Calls add(node, component, entry) for every node and component of element e of b, the
  /// entry that of its tangent at the positions X (the block's kernels, one element).
  template <class Add>
  void operator()(const ElementBlock& b, int e, const NodePositions& X, Add&& add) {
    const auto en = b.nodes(e);
    const size_t nd = static_cast<size_t>(b.dofs_per_element());
    r_.assign(nd, 0.0), K_.assign(nd * nd, 0.0);
    b.internal(std::span<const int>(&e, 1), X, r_.data(), K_.data());
    for (size_t a = 0; a < en.size(); ++a)
      for (size_t c = 0; c < 3; ++c)
        add(en[a], static_cast<int>(c), K_[(3 * a + c) * nd + 3 * a + c]);
  }

 private:
  // The kernels store fixed-size Eigen blocks into these: aligned as Eigen wants.
  std::vector<double, Eigen::aligned_allocator<double>> r_, K_;
};

}  // namespace velum
