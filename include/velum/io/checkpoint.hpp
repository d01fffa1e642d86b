// DIR/checkpoint.bin: what `velum run MODEL --restart DIR` needs to go on exactly as the run
// would have (docs/model-format.md, output.checkpoint): the analysis's Checkpoint and where the
// results files stood. Binary, this machine's byte order, ending in a checksum, written through a
// temporary file and a rename (a run killed while writing leaves the last one whole).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "velum/analysis/analysis.hpp"

namespace velum::io {

struct CheckpointFile {
  int dofs = 0;             ///< the equations of the model that wrote it
  std::string model;        ///< the model file's name, for messages
  int processes = 1;        ///< the processes that wrote it (the frames' pieces)
  std::string fingerprint;  ///< what a restarted model must match (run_model.cpp)
  Checkpoint run;
  long history_bytes = 0, steps_bytes = 0;  ///< history.csv and steps.csv then
  std::vector<double> frame_times;          ///< the frames then
};

/// Throws OutputError.
void write_checkpoint(const std::filesystem::path& path, const CheckpointFile& c);
/// Throws std::runtime_error naming the file when it is missing, not a regular file, short, not
/// a checkpoint, fails its checksum or holds a value no run writes (a time that is not finite).
CheckpointFile read_checkpoint(const std::filesystem::path& path);

}  // namespace velum::io
