// The files of `velum pattern` (docs/patterns.md): patterns.json, each panel's DXF (R12, layers
// CUT, SEAM, TEXT) and SVG, and the flattening strain on the 3-D shape for ParaView.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "velum/analysis/flatten.hpp"

namespace velum::io {

struct PatternPanel {
  std::string name;
  FlatPanel flat;              ///< flat coordinates before compensation
  std::vector<long> node_ids;  ///< the user's ids of flat.nodes
  std::vector<Vec2> seam;      ///< the outline after compensation (the sewn line)
  std::vector<Vec2> cut;       ///< the seam offset outwards by the allowance (the cut line)
};

/// The seam line (the outline shrunk by warp along u and fill along v) and the cut line (it
/// offset outwards by `allowance`) of a flattened panel.
void outline_panel(PatternPanel& p, double warp, double fill, double allowance);

/// Writes DIR/patterns.json, DIR/<panel>.dxf, DIR/<panel>.svg and DIR/flattening.vtu (the
/// panels on the 3-D shape `x` with the strain left by flattening per element). Throws
/// std::runtime_error when a file cannot be written.
void write_patterns(const std::filesystem::path& dir, const std::vector<PatternPanel>& panels,
                    const NodePositions& x, double warp, double fill, double allowance);

/// The DXF (R12 ASCII) text of one panel: CUT and SEAM closed polylines, its name and area.
std::string panel_dxf(const PatternPanel& p);

}  // namespace velum::io
