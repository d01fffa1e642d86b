// The `stress_map` sheet law of the model file: its keys, and the CSV files (the grid of warp
// and fill stresses, the shear curve) it names relative to the model file, checked with
// messages naming the file, line and key (docs/materials.md, "Stress maps").
#pragma once

#include <optional>
#include <string>

#include "reader_context.hpp"
#include "velum/material/sheet_law.hpp"

namespace velum::io::model_file {

std::optional<SheetLaw> parse_stress_map(ReaderContext& r, const Node& m, const std::string& name,
                                         const std::string& p);

}  // namespace velum::io::model_file
