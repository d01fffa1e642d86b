// The commands of the `velum` executable (app/main.cpp only parses arguments): `run` solves a
// model file and writes its results, `check` validates it and prints statistics. Both return
// the process exit status of MODEL_FORMAT.md: 0 solved, 1 bad input, 2 solve failed, 3 I/O.
#pragma once

#include <filesystem>
#include <optional>

namespace velum::io {

inline constexpr int kExitOk = 0, kExitBadInput = 1, kExitSolveFailed = 2, kExitIo = 3;

struct RunOptions {
  std::filesystem::path model;
  std::optional<std::filesystem::path> output;  ///< overrides output.directory
  int threads = 0;                              ///< 0: OpenMP's default
  bool quiet = false;
  std::optional<std::filesystem::path> restart;  ///< a run's folder: go on from its checkpoint
};

int run_command(const RunOptions& options);
int check_command(const std::filesystem::path& model);

}  // namespace velum::io
