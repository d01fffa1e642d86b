// The run driver (shared by `velum run` and the Python module): a model already read is built,
// analysed (analysis/analysis.hpp's one entry point) and written (io/), with the MPI sharing
// (parallel/), checkpoints and restarts orchestrated here. It returns what happened instead of
// printing errors; the exit statuses are those of docs/model-format.md: 0 solved, 1 bad
// input, 2 solve failed, 3 I/O (including an output folder in use by another run), 130 / 143
// interrupted by SIGINT / SIGTERM.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "velum/io/model_reader.hpp"
#include "velum/io/results_writer.hpp"

namespace velum::run {

using io::ModelInput;
using io::RunSummary;

inline constexpr int kExitOk = 0, kExitBadInput = 1, kExitSolveFailed = 2, kExitIo = 3;
/// Stopped by a signal after finishing a step: 128 + the signal, as a shell reports it.
inline constexpr int kExitInterrupted = 130, kExitTerminated = 143;  // SIGINT, SIGTERM

/// How run_model runs: where it writes, its threads, its console and the caller's observer.
struct RunControls {
  std::optional<std::filesystem::path> output;   ///< overrides output.directory
  int threads = 0;                               ///< 0: OpenMP's default
  bool quiet = false;                            ///< no progress or statistics on stderr
  std::optional<std::filesystem::path> restart;  ///< a run's folder: go on from its checkpoint
  /// Called after each accepted step (and once at t0 with step 0), after its results are
  /// written; returning false stops the run (it then ends as "failed", `stopped` set). It must
  /// not throw: the caller keeps its own errors and returns false.
  std::function<bool(const AcceptedStep&)> on_step;
  /// When the run started (summary.json's wall_seconds count from here): the command line
  /// starts the clock before it reads the model.
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
};

/// What a run did. `status` is the exit status; `errors` the messages the command line prints
/// after "error: " (empty when solved).
struct RunOutcome {
  int status = kExitOk;
  RunSummary summary;  ///< as in summary.json (written unless status is kExitBadInput/kExitIo)
  std::filesystem::path directory;
  bool stopped = false;  ///< on_step asked to stop
  std::vector<std::string> errors;
};

/// Solves `input` and writes its results (history.csv, steps.csv, frames, summary.json) as
/// `velum run` does, printing its progress and statistics on stderr unless quiet. Models that
/// cannot be set up, I/O failures and failed solves are reported in the outcome, not thrown.
RunOutcome run_model(ModelInput& input, const RunControls& controls);

}  // namespace velum::run
