// Checks of a model file's YAML structure that yaml-cpp lets through: a key given twice in one
// mapping (yaml-cpp keeps the first silently, so a second `materials:` section would vanish)
// and nesting deeper than any model needs. Aliases are followed once (a node reached twice is
// not walked again, so an alias bomb costs no more than the file).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "velum/io/model_reader.hpp"  // kMaxYamlDepth

namespace velum::io::model_file {

/// "file:line: key: problem" for each duplicate key (naming both lines) and the first node
/// nested deeper than kMaxYamlDepth.
std::vector<std::string> yaml_structure_problems(const YAML::Node& root, const std::string& file);

}  // namespace velum::io::model_file
