// Reads a model given as a YAML node built in memory (the Python module builds one from a
// dict). Separate from model_reader.hpp so that only callers that hold YAML nodes see
// yaml-cpp. Nodes without a position (built in memory) give messages that name the key alone.
#pragma once

#include <yaml-cpp/yaml.h>

#include "velum/io/model_reader.hpp"

namespace velum::io {

/// Reads and validates a model from its root node. Throws InputError.
ModelInput read_model(const YAML::Node& root, const ModelSource& source);

}  // namespace velum::io
