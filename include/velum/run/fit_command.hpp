// `velum fit BIAXIAL.csv [options]`: fits a linear orthotropic law and a stress map to biaxial
// tests (docs/materials.md, "Fitting biaxial tests") by running the Python module velum.fit
// with Debian's /usr/bin/python3: from the build tree (python/ beside the executable, put on
// PYTHONPATH) or as installed (where that interpreter finds the package).
#pragma once

#include <string>
#include <vector>

namespace velum::run {

/// Runs `python3 -m velum.fit` with `args` (passed on as given); returns its exit status (0,
/// 1 for bad input with its message on stderr, 3 when the interpreter cannot run).
int fit_command(const std::vector<std::string>& args);

}  // namespace velum::run
