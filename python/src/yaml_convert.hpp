// Python objects <-> YAML nodes for the velum module: a model dict becomes the YAML node the
// reader reads (so a model edited in Python is read exactly as its file would be), and a YAML
// file becomes plain Python objects. Numbers keep every bit both ways.
#pragma once

#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace velum::python {

/// Python -> YAML: dict (any Mapping) -> map, list/tuple -> sequence, numpy arrays -> nested
/// sequences, int/float/bool/None/str/os.PathLike -> scalars (floats in their shortest form
/// that reads back to the same double). Throws TypeError naming `path` for anything else.
YAML::Node to_yaml(pybind11::handle obj, const std::string& path);

/// YAML -> Python: maps -> dict (file order), sequences -> list, plain scalars -> int, float,
/// bool (true/false only), None (null, ~, empty) or str; quoted scalars stay str.
pybind11::object from_yaml(const YAML::Node& node);

}  // namespace velum::python
