// `velum pattern MODEL.yaml|DIR -o PDIR`: the cutting patterns of the model's panels
// (docs/patterns.md).
#pragma once

#include <filesystem>

namespace velum::run {

/// Flattens each panel named in the model's `patterns:` (of the model file, or of DIR's found
/// form DIR/form.yaml) and writes PDIR (pattern_writer.hpp). Returns the exit status.
int pattern_command(const std::filesystem::path& input, const std::filesystem::path& output);

}  // namespace velum::run
