// `velum partition MODEL -n P -o DIR`: the model split for P MPI processes, one part file per
// process (io/mesh_part.hpp), so that a run on P processes with `mesh.parts: DIR` has no
// process hold the whole mesh (docs/parallel.md "Reading the mesh in parts").
#pragma once

#include <filesystem>

namespace velum::run {

/// Reads the whole model once (on this one process), computes each process's piece by
/// share_model's rules (the row rule) and writes DIR/part_0.txt .. part_{P-1}.txt. Returns
/// the exit status (bad input 1, I/O 3).
int partition_command(const std::filesystem::path& model, int parts,
                      const std::filesystem::path& dir);

}  // namespace velum::run
