// The commands of the `velum` executable (app/main.cpp only parses arguments): `run` solves a
// model file and writes its results, `check` validates it and prints statistics. Both return
// the process exit status of MODEL_FORMAT.md: 0 solved, 1 bad input, 2 solve failed, 3 I/O
// (including an output folder in use by another run), 130 / 143 interrupted by SIGINT / SIGTERM.
// run_model is the run itself, shared by `velum run` and the Python module: it takes a model
// already read and returns what happened instead of printing errors.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "velum/io/checkpoint.hpp"
#include "velum/io/model_reader.hpp"
#include "velum/io/results_writer.hpp"
#include "velum/io/run_control.hpp"

namespace velum::io {

inline constexpr int kExitOk = 0, kExitBadInput = 1, kExitSolveFailed = 2, kExitIo = 3;
/// Stopped by a signal after finishing a step: 128 + the signal, as a shell reports it.
inline constexpr int kExitInterrupted = 130, kExitTerminated = 143;  // SIGINT, SIGTERM

struct RunOptions {
  std::filesystem::path model;
  std::optional<std::filesystem::path> output;  ///< overrides output.directory
  int threads = 0;                              ///< 0: OpenMP's default
  bool quiet = false;
  std::optional<std::filesystem::path> restart;  ///< a run's folder: go on from its checkpoint
};

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

/// run_model for a model with steps (src/io/staged_run.cpp).
RunOutcome run_staged(ModelInput& input, const RunControls& controls);
/// `velum check`'s lines for a model's steps (none without steps).
std::string describe_steps(const ModelInput& input);
/// The output folder, its lock and the results writer of a run (`resume`: a restart).
bool open_results(const ModelInput& input, MechanicalSystem& system,
                  const std::filesystem::path& dir, const std::optional<CheckpointFile>& resume,
                  RunOutcome& out, std::optional<OutputLock>& lock,
                  std::unique_ptr<ResultsWriter>& writer);

/// A run stopped by SIGINT or SIGTERM (sig): status "interrupted", `reason`, exit 130 / 143.
void mark_interrupted(int sig, const std::string& reason, RunSummary& summary, RunOutcome& out);
/// Times the run (wall since `started`, CPU since `cpu_at_start`, threads) and writes
/// summary.json; false, with the outcome set to an I/O failure, when it cannot be written.
bool finish_summary(ResultsWriter& writer, RunSummary& summary,
                    std::chrono::steady_clock::time_point started, double cpu_at_start,
                    RunOutcome& out);

int run_command(const RunOptions& options);
int check_command(const std::filesystem::path& model);
/// `velum import DECK.inp -o MODEL.yaml` (src/io/import_command.cpp).
int import_command(const std::filesystem::path& deck, const std::filesystem::path& output);

}  // namespace velum::io
