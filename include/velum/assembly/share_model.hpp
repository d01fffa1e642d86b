// Cuts a model shared between MPI processes down to this process's piece (docs/parallel.md):
// the elements shared out, the nodes renumbered; what a process holds is parallel/model_piece.hpp.
#pragma once

#include <string>
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

/// One sharing for several models of one mesh (the steps of a staged run, each with its own
/// boundary conditions): every element computed by the same process in every step, and every
/// step's piece holding the same nodes in the same order (the union over the steps of the nodes
/// each process needs), so that the state goes on from step to step node by node.
struct MeshSharing {
  /// Per element through the blocks: the process that computes it (empty until the first
  /// share_model with this sharing fills it from its model and partition).
  std::vector<int> cell_owner;
  ElementPartition partition = ElementPartition::kRows;  ///< the partition cell_owner follows
  std::string partition_note;  ///< why the partition asked for was not used (empty: it was)
  /// Per node of the whole mesh: the processes owning one of its equations in some model
  /// (add_equation_owners, for every model before any of them is cut).
  std::vector<std::vector<int>> equation_owners;
};

/// Adds the owners of `whole`'s equations to sharing.equation_owners (a whole model).
void add_equation_owners(MeshSharing& sharing, const Model& whole);

/// share_model with the elements shared as in `sharing` (filled on the first call) and the
/// nodes held by the owners of every model's equations. Collective; nothing on one process.
std::vector<int> share_model(Model& model, ElementPartition partition, MeshSharing& sharing);

}  // namespace velum
