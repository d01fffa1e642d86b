// `velum plot DIR [options]`: PNGs of a results folder, drawn by tools/velum_plot.py (matplotlib)
// run with Debian's /usr/bin/python3. The script is found next to the executable: in the build
// tree (share/velum/ beside it) and after `make install` (../share/velum/).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace velum::run {

/// The plotting script for the running executable, or nothing when it is not installed.
std::optional<std::filesystem::path> plot_script();

/// A Python helper `name` installed beside the running executable (share/velum/ in the build
/// tree, ../share/velum/ installed), or nothing.
std::optional<std::filesystem::path> share_script(const char* name);

/// Runs the script with `args` (DIR and its options, passed on as given); returns its exit
/// status (0, or 1 for bad input with its message on stderr).
int plot_command(const std::vector<std::string>& args);

}  // namespace velum::run
