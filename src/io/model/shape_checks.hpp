// Checks of each element's reference shape before any block is built: a node repeated in one
// element, a surface that folds over or crosses itself (a signed area ratio not positive at a
// node, the centre or an integration point), a line whose middle node lies beyond an end.
// The integration points alone miss a bow-tie quad or a folded mid-side node: their Jacobian
// can stay positive there while the element crosses itself.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "velum/model/element_block.hpp"

namespace velum::io::model_file {

struct ShapeProblem {
  int element = -1;  ///< index in the group; -1: every element is usable
  std::string what;  ///< e.g. "repeats node 4", "crosses itself or folds over at node 3"
};

/// The first unusable element of a group of `type` (per element, its shape's node count of
/// indices into X; `ids` the user's node ids of X's columns).
ShapeProblem check_shapes(std::string_view type, std::span<const int> conn, const NodePositions& X,
                          std::span<const long> ids);

}  // namespace velum::io::model_file
