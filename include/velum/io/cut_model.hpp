// The model file `velum seams` writes: the model's mesh at its shape, cut into panels (element
// sets), the sections and loads of a cut set given per panel (docs/patterns.md, "Seams").
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "velum/io/model_reader.hpp"

namespace velum::io {

struct CutMesh {
  NodePositions x;             ///< every node at the shape: the model's, then the new ones
  std::vector<long> node_ids;  ///< per node of x
  struct Element {
    long id;
    std::string type;
    std::vector<long> nodes;
  };
  /// Element sets in the order written: the panels, then the sets not cut (cables).
  std::vector<std::pair<std::string, std::vector<Element>>> sets;
  std::map<std::string, std::vector<long>> node_sets;
  /// A set that was cut -> the panels its elements went to (its sections and loads are given
  /// once per panel).
  std::map<std::string, std::vector<std::string>> renamed;
  std::vector<std::string> panels;
};

/// Writes `file`: the model's YAML with the mesh inline (nodes at the shape, no
/// mesh.positions, reference_positions or panel_references), node sets as id lists, the
/// sections and loads that name a cut set repeated for each of its panels (a list of sets
/// naming it gets its panels), patterns.panels the panels (patterns.seams dropped: they are
/// cut), output.directory dropped. Throws OutputError.
void write_cut_model(const ModelInput& input, const CutMesh& mesh,
                     const std::filesystem::path& file);

}  // namespace velum::io
