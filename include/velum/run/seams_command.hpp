// `velum seams MODEL.yaml|DIR -o OUT.yaml`: the model's surface cut into panels along the
// seams of its `patterns.seams` (docs/patterns.md, "Seams").
#pragma once

#include <filesystem>

#include "velum/io/model_reader.hpp"

namespace velum::run {

/// Reads the model (or DIR's found form, DIR/form.yaml), cuts it and writes OUT.yaml.
/// Returns the exit status.
int seams_command(const std::filesystem::path& input, const std::filesystem::path& output);

/// Cuts the model `in` (read from `model_file`) along its seams and writes the model with
/// its panels to `output` (cut_model.hpp), read back as a check. Returns the exit status
/// (problems said on stderr naming the file, line and key).
int cut_along_seams(const io::ModelInput& in, const std::filesystem::path& model_file,
                    const std::filesystem::path& output);

}  // namespace velum::run
