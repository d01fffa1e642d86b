// Reads a model given as a YAML node built in memory (the Python module builds one from a
// dict). Separate from model_reader.hpp so that only callers that hold YAML nodes see
// yaml-cpp. Nodes without a position (built in memory) give messages that name the key alone.
#pragma once

#include <yaml-cpp/yaml.h>

#include "velum/io/model_reader.hpp"

namespace velum::io {

/// A model file's YAML tree, loaded as `velum run` loads it (no validation of the model itself):
/// refused if not a regular file, too large, holding a second document, a syntax error, a key
/// given twice or nested too deep. Throws InputError.
YAML::Node load_model_yaml(const std::filesystem::path& file);

/// Reads and validates a model from its root node. Throws InputError.
ModelInput read_model(const YAML::Node& root, const ModelSource& source);

}  // namespace velum::io
