// What one MPI process holds of a model shared between processes (docs/parallel.md). Every
// process reads the whole model; share_model() then shares the elements out and cuts the
// model down to this process's piece: its own elements' section data and the nodes it holds,
// renumbered 0 .. n-1 in their global order. Every per-node array from there on (positions,
// displacements, forces, the output's fields) is over the piece's nodes only, so that the
// memory of a process falls with the processes. On one process nothing is shared and the
// model is left whole (Model::piece stays null). Plain data on the ground floor, so that the
// Model that holds it may include it; the cutting itself is assembly/share_model.hpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "velum/parallel/element_partition.hpp"

namespace velum {

struct ModelPiece {
  int global_nodes = 0;          ///< nodes of the whole model
  std::vector<int> global_node;  ///< per local node: its index in the whole model (ascending)
  /// 3 per local node: its components' equations in the global numbering (-1: eliminated).
  std::vector<int> equation;
  int global_equations = 0;
  bool whole_nodes = true;  ///< every node of the whole model has all three equations or none
  double size = 0;          ///< the whole model's size: its bounding box's diagonal

  /// Per block: the elements this process computes (ascending; indices of the whole block).
  std::vector<std::vector<int>> own;
  ElementPartition partition = ElementPartition::kRows;
  std::string partition_note;  ///< why the partition asked for was not used (empty: it was)

  /// Per local node: this process adds the node's nodal terms (point loads, drag, gravity and
  /// edge-load vectors) to its share of a sum: the lowest process whose elements hold it,
  /// the first when no element does.
  std::vector<char> kept;
  /// Local nodes whose diagonal block this process's matrix share holds without an element
  /// of its own reaching them (the first process: point masses' nodes, nodes in no element).
  std::vector<int> lone;
  /// Local nodes no element holds (the first process only: the frames' points of them).
  std::vector<int> bare;
  /// This process's nodes that another process holds too (ascending local index, so global
  /// order).
  std::vector<int> shared;
  /// The processes holding one of them (ascending rank), and per neighbour the positions in
  /// `shared` of the nodes it holds too (ascending): both processes list the same nodes in the
  /// same order, so a shared-node sum is one message each way per neighbour.
  std::vector<int> neighbours;
  std::vector<std::vector<int>> shared_with;
  /// Nodes held by elements of more than one process (the partition's cut, as reported).
  long element_cut = 0;
};

}  // namespace velum
