// Cuts a model shared between MPI processes down to this process's piece (docs/parallel.md):
// the elements shared out, the nodes renumbered; what a process holds is parallel/model_piece.hpp.
#pragma once

#include <vector>

#include "velum/model/model.hpp"
#include "velum/parallel/element_partition.hpp"
#include "velum/parallel/model_piece.hpp"

namespace velum {

/// Shares the model's elements between the processes (`partition`; PT-Scotch through PETSc
/// when asked for and available, else the row rule) and cuts `model` down to this process's
/// piece: its nodes renumbered, its own elements' connectivity and section data kept (other
/// elements keep their index but no data: ElementBlock::keep_piece), node sets, point masses
/// and loads (Load::keep_piece) restricted to the piece, and model.piece set. Returns, per node of
/// the whole model, its local index (-1: not held here), for references the caller keeps (history
/// nodes). A collective call; on one process it does nothing and returns {}. Throws
/// std::invalid_argument when the model cannot be numbered.
std::vector<int> share_model(Model& model, ElementPartition partition);

}  // namespace velum
