// The commands of the `velum` executable (app/main.cpp only parses arguments): `run` solves a
// model file and writes its results (run_model.hpp), `check` validates it and prints
// statistics, `import` converts an Abaqus deck. Each returns the process exit status of
// run_model.hpp.
#pragma once

#include <filesystem>
#include <optional>

#include "velum/run/run_model.hpp"

namespace velum::run {

struct RunOptions {
  std::filesystem::path model;
  std::optional<std::filesystem::path> output;  ///< overrides output.directory
  int threads = 0;                              ///< 0: OpenMP's default
  bool quiet = false;
  std::optional<std::filesystem::path> restart;  ///< a run's folder: go on from its checkpoint
};

int run_command(const RunOptions& options);
int check_command(const std::filesystem::path& model);
/// `velum import DECK.inp -o MODEL.yaml` (import_command.cpp).
int import_command(const std::filesystem::path& deck, const std::filesystem::path& output);

}  // namespace velum::run
