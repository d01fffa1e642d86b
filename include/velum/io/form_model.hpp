// DIR/form.yaml: the model of a form-finding run with the found shape, ready for the next
// analysis (docs/fabric-structures.md).
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>

#include "velum/io/model_reader.hpp"

namespace velum::io {

/// Writes `file`: the model's YAML with `mesh.positions` holding the found coordinates x of
/// every node (3 x nodes, in the model's node order), the mesh file named relative to it,
/// analysis.type static (form_finding settings dropped, the rest kept), output.directory
/// dropped (results of the next run go to its folder's `out`). The sections keep their
/// prestress: on the found shape it is the stress in equilibrium. Throws OutputError.
void write_form_model(const ModelInput& input, const NodePositions& x,
                      const std::filesystem::path& file);

/// What a model written from a run shares (form.yaml, `velum pattern`'s roundtrip.yaml): the
/// model's YAML with its mesh file named relative to `file`'s folder (absolute where no
/// relative path leads there), mesh.positions at x, analysis.type static (form_finding
/// dropped) and output.directory dropped. Throws OutputError when the YAML cannot be read.
YAML::Node model_at_shape(const ModelInput& input, const NodePositions& x,
                          const std::filesystem::path& file);
/// Writes `root` to `file` under a comment line `comment`. Throws OutputError.
void write_model_yaml(const YAML::Node& root, const std::string& comment,
                      const std::filesystem::path& file);
/// A node's row of mesh.positions: [id, x, y, z], each number in its shortest round-trip form.
YAML::Node position_row(long id, const Vec3& p);

}  // namespace velum::io
