// Cuts a model shared between MPI processes down to this process's piece (docs/parallel.md):
// the elements shared out, the nodes renumbered; what a process holds is parallel/model_piece.hpp.
#pragma once

#include <string>
#include <vector>

#include "velum/assembly/dof_map.hpp"
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
/// The same for `count` processes (`velum partition`, on one process).
void add_equation_owners(MeshSharing& sharing, const Model& whole, int count);

/// Per element through the blocks: the process of `count` that computes it by the row rule
/// (the owner of the row of its lowest equation in `whole`, the model's numbering).
std::vector<int> row_rule_owners(const Model& model, const DofMap& whole, int count);

/// What process `rank` of `count` holds of `model` (whole, left as it is) with its elements
/// computed by `cell_owner` (per element through the blocks) and, for a staged run, the nodes
/// of every model's equation owners held too: share_model's rules without MPI, so that
/// `velum partition` computes every part on one process. `local_of`: per node of the whole
/// model its index on the piece (-1: not held). Partition and its note are left to the caller.
ModelPiece plan_piece(const Model& model, const DofMap& whole, int rank, int count,
                      const std::vector<int>& cell_owner,
                      const std::vector<std::vector<int>>* equation_owners,
                      std::vector<int>& local_of);

/// share_model with the elements shared as in `sharing` (filled on the first call) and the
/// nodes held by the owners of every model's equations. Collective; nothing on one process.
std::vector<int> share_model(Model& model, ElementPartition partition, MeshSharing& sharing);

}  // namespace velum
