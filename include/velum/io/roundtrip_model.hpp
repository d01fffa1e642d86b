// PDIR/roundtrip.yaml of `velum pattern`: the compensated flat panels sewn back onto the shape
// (mesh.panel_references), a model whose run shows the stress the panels reach against the
// designed prestress (docs/patterns.md, "Round trip").
#pragma once

#include <filesystem>
#include <vector>

#include "velum/io/model_reader.hpp"
#include "velum/io/pattern_writer.hpp"

namespace velum::io {

/// Writes `file`: the model's YAML with every node at the shape x (mesh.positions; no
/// mesh.reference_positions), each panel's compensated flat coordinates [u (1 - warp),
/// v (1 - fill), 0] as its mesh.panel_references, the panels' sections without prestress and
/// with the default axes (global x: the flat panel's warp u), analysis.type static
/// (form_finding, steps, patterns and output.directory dropped). Cables and loads as given.
/// Throws OutputError.
void write_roundtrip_model(const ModelInput& input, const NodePositions& x,
                           const std::vector<PatternPanel>& panels, double warp, double fill,
                           const std::filesystem::path& file);

}  // namespace velum::io
