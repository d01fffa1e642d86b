// One part of a model split for several MPI processes (`velum partition`, docs/parallel.md
// "Reading the mesh in parts"): what process `part` of `parts` needs to build its piece of the
// model (parallel/model_piece.hpp) without ever holding the whole mesh. The split writes one
// text file per part, DIR/part_K.txt (its layout is in docs/model-format.md); the model
// reader reads the one of its process where the model gives `mesh.parts: DIR`. Coordinates in
// the model's units, written with 17 significant digits (read back exactly).
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "velum/load/edge_load.hpp"
#include "velum/math/types.hpp"

namespace velum::io {

struct MeshPart {
  int part = 0, parts = 1;
  int global_nodes = 0;  ///< nodes of the whole model
  double size = 0;       ///< the whole model's bounding-box diagonal
  long element_cut = 0;

  // The piece's nodes, in the whole model's order (their local numbering).
  std::vector<long> node_id;
  std::vector<int> global_node;                     ///< index in the whole model
  NodePositions X;                                  ///< 3 x nodes
  std::vector<char> kept;                           ///< ModelPiece::kept
  std::vector<int> lone, bare, shared, neighbours;  ///< ModelPiece's, local node indices
  std::vector<std::vector<int>> shared_with;

  /// The numbering of one model: the model without steps, or each analysis step's in order.
  struct Numbering {
    int global_equations = 0;
    bool whole_nodes = true;
    std::vector<int> equation;  ///< 3 per node: global equation (-1: eliminated)
    int path_equation = -1;     ///< displacement control's equation (-1: none)
    /// Per edge load of the model (in the order of its loads): the mesh's boundary edges it
    /// loads among this part's elements (block and element indices of the whole model).
    std::vector<std::vector<EdgeLoad::Edge>> edge_loads;
  };
  std::vector<Numbering> numberings;

  /// One element group (one block of the whole model, in order): this part's elements of it.
  struct Group {
    std::string set, type;
    int whole = 0;               ///< elements in the whole block
    std::vector<int> own;        ///< their index in the whole block, ascending
    std::vector<long> ids;       ///< their ids
    std::vector<long> node_ids;  ///< their connectivity by node id, flattened
  };
  std::vector<Group> groups;

  /// Node sets (the mesh's and the model file's) and each element set's nodes, cut to this
  /// part: ids of its nodes (possibly none).
  std::map<std::string, std::vector<long>> node_sets, element_set_nodes;
  /// Per history entry: the element (block, element of the whole model) and natural
  /// coordinates of a point or element entry (block -1: none).
  struct Place {
    int block = -1, element = -1;
    std::array<double, 2> xi{0, 0};
  };
  std::vector<Place> history;
  /// Nodes that sections name as sheet-axes points, wherever they are: id and coordinates.
  std::vector<std::pair<long, Vec3>> points;
};

/// DIR/part_K.txt.
std::filesystem::path mesh_part_file(const std::filesystem::path& dir, int part);
/// Writes a part; throws std::runtime_error naming the file when it cannot.
void write_mesh_part(const std::filesystem::path& file, const MeshPart& part);
/// Reads a part; throws std::runtime_error "file:line: text" when it is not one.
MeshPart read_mesh_part(const std::filesystem::path& file);

}  // namespace velum::io
