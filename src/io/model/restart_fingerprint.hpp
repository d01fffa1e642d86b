// What of a model a restart must match besides its materials and sections (restart.cpp): the
// analysis (but time.end), the loads, the boundary, the functions, masses, contacts and rigid
// bodies as read, and the mesh as built (node coordinates, elements, supported nodes).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "velum/model/model.hpp"

namespace velum::io::model_file {

/// One line per fact, sections headed "[name]", so that a mismatch can name its line.
std::string restart_fingerprint(const YAML::Node& root, const Model& model);

}  // namespace velum::io::model_file
