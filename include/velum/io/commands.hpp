// The commands of the `velum` executable (app/main.cpp only parses arguments): `run` solves a
// model file and writes its results, `check` validates it and prints statistics. Both return
// the process exit status of MODEL_FORMAT.md: 0 solved, 1 bad input, 2 solve failed, 3 I/O
// (an output folder another run is writing into, too), 130 / 143 stopped by SIGINT / SIGTERM.
// (including an output folder in use by another run), 130 / 143 interrupted by SIGINT / SIGTERM.
#pragma once

#include <filesystem>
#include <optional>

namespace velum::io {

inline constexpr int kExitOk = 0, kExitBadInput = 1, kExitSolveFailed = 2, kExitIo = 3;
/// Stopped by a signal after finishing a step: 128 + the signal, as a shell reports it.
inline constexpr int kExitInterrupted = 130, kExitTerminated = 143;  // SIGINT, SIGTERM

struct RunOptions {
  std::filesystem::path model;
  std::optional<std::filesystem::path> output;  ///< overrides output.directory
  int threads = 0;                              ///< 0: OpenMP's default
  bool quiet = false;
};

int run_command(const RunOptions& options);
int check_command(const std::filesystem::path& model);

}  // namespace velum::io
