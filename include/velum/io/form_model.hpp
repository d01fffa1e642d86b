// DIR/form.yaml: the model of a form-finding run with the found shape, ready for the next
// analysis (docs/fabric-structures.md).
#pragma once

#include <filesystem>

#include "velum/io/model_reader.hpp"

namespace velum::io {

/// Writes `file`: the model's YAML with `mesh.positions` holding the found coordinates x of
/// every node (3 x nodes, in the model's node order), a mesh file named by its absolute path,
/// analysis.type static (form_finding settings dropped, the rest kept), output.directory
/// dropped (results of the next run go to its folder's `out`). The sections keep their
/// prestress: on the found shape it is the stress in equilibrium. Throws OutputError.
void write_form_model(const ModelInput& input, const NodePositions& x,
                      const std::filesystem::path& file);

}  // namespace velum::io
