// The sheet laws a model file names in `materials: {name: {type: ...}}`: one row per law, its
// `type:` name and the parser that reads its parameters. A new sheet law is its class
// (material/), its row here and its test.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "reader_context.hpp"
#include "velum/material/sheet_law.hpp"

namespace velum::io::model_file {

/// Reads the law of material `name` from its mapping m (path p, "materials.name"): checks
/// the keys (type and density are the material's), reports bad values through r and returns
/// nullopt when the law cannot be built. A MaterialError or std::invalid_argument thrown while
/// building the law is reported by the caller.
using SheetLawParser = std::optional<SheetLaw> (*)(ReaderContext& r, const Node& m,
                                                   const std::string& name, const std::string& p);

struct SheetLawEntry {
  std::string_view type;
  SheetLawParser parse;
};

/// Every sheet law of the model file, in the order the messages list them.
std::span<const SheetLawEntry> sheet_law_table();
/// The row of `type`, or null.
const SheetLawEntry* find_sheet_law(std::string_view type);

}  // namespace velum::io::model_file
