// A mesh as read from a model file or a Gmsh file, before it becomes a Model: nodes with the
// user's ids, elements grouped by (set, type) in Gmsh node order, and named node sets. Ids are
// the user's; coordinates are in the user's units.
#pragma once

#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::io {

struct MeshNode {
  long id = 0;
  Vec3 x = Vec3::Zero();
};

struct ElementGroup {
  std::string set;
  std::string type;            ///< tri3 tri6 quad4 quad8 quad9 cable2 cable3
  std::vector<long> ids;       ///< element ids (the user's, for messages)
  std::vector<long> node_ids;  ///< connectivity by node id, flattened
  int line = 0;                ///< 1-based line in the model file (0: from a mesh file)
};

struct MeshData {
  std::vector<MeshNode> nodes;
  std::vector<ElementGroup> groups;
  std::map<std::string, std::vector<long>> node_sets;
};

/// A mesh file that cannot be read; the message names the file and the problem.
class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a Gmsh .msh file (MSH 2.2 or 4.1, ASCII or binary). Physical groups become named node
/// sets (every dimension) and element sets (lines and surfaces); unnamed groups are named by
/// their tag. Without physical groups, every line and surface element goes to the set "all".
/// Throws MeshFileError.
MeshData read_gmsh(const std::filesystem::path& file);

/// The same from the file's bytes; `name` names the file in messages.
MeshData read_gmsh_text(std::string_view bytes, const std::string& name);

/// Velum's element type name of a Gmsh element type number, or empty when unsupported.
std::string type_of_gmsh(int gmsh_type);

}  // namespace velum::io
