// Abaqus / CalculiX input decks (.inp): the keywords a membrane model uses
// (docs/inp-import.md). A deck is read in two ways:
//  - as a mesh file (`mesh.file: model.inp` in a YAML model): its nodes, elements and sets,
//    every other keyword reported as not read;
//  - as a whole model (`velum import model.inp -o model.yaml`): the mesh and the materials,
//    sections, orientations, boundary conditions, loads, amplitudes and the step, written
//    out as a Velum YAML model.
// Keywords, options and names are case-insensitive (Abaqus's rules); names keep the spelling
// of their definition. Anything the reader does not map is reported with the file, line and
// keyword: an error when it would change the answer, a warning when it cannot (output
// requests, *HEADING, ...). Nothing is ignored silently.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/io/mesh_data.hpp"
#include "velum/math/types.hpp"

namespace velum::io {

/// Bad or unsupported input in a deck: every problem found, each "file:line: *KEYWORD: text".
class InpError : public std::runtime_error {
 public:
  explicit InpError(std::vector<std::string> messages);
  const std::vector<std::string>& messages() const { return messages_; }

 private:
  std::vector<std::string> messages_;
};

/// The nodes, elements and sets of a deck as a mesh (in Gmsh node order, MeshData's
/// convention). Each element goes to the first element set naming it, in the order of the
/// file (the ELSET= of its *ELEMENT line, or "all" without one); an *ELSET whose elements are
/// already in other sets is a node set only, said in a warning. Every *NSET and *ELSET is a
/// node set. Keywords other than *NODE, *ELEMENT, *NSET, *ELSET, *INCLUDE and *HEADING give
/// one warning each ("not read: mesh.file takes the mesh only"). Throws InpError (which
/// MeshFileError callers may report as is) on bad input.
MeshData read_inp_mesh(const std::filesystem::path& file, std::vector<std::string>& warnings);

/// `velum import`: the deck as a Velum YAML model (text), the mesh written inline. Throws
/// InpError listing every problem; `warnings` receives what was mapped approximately or left
/// out harmlessly.
std::string import_inp(const std::filesystem::path& file, std::vector<std::string>& warnings);

}  // namespace velum::io
