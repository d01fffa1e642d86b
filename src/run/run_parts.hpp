// The run driver's parts shared between its files (src/run/): the staged run, the results
// folder and the summary's last lines.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "velum/io/checkpoint.hpp"
#include "velum/io/run_control.hpp"
#include "velum/run/run_model.hpp"

namespace velum::run {

using namespace velum::io;  // the readers' and writers' types, as io's own code names them

/// run_model for a model with steps (staged_run.cpp).
RunOutcome run_staged(ModelInput& input, const RunControls& controls);
/// `velum check`'s lines for a model's steps (none without steps).
std::string describe_steps(const ModelInput& input);
/// The output folder, its lock and the results writer of a run (`resume`: a restart).
bool open_results(const ModelInput& input, MechanicalSystem& system,
                  const std::filesystem::path& dir, const std::optional<CheckpointFile>& resume,
                  RunOutcome& out, std::optional<OutputLock>& lock,
                  std::unique_ptr<ResultsWriter>& writer);

/// Under mpirun: the history's nodes renumbered to the piece's (local_of: share_model's), -1
/// or left out of a reaction's list where another process holds them.
void renumber_history(std::vector<HistoryEntry>& history, const std::vector<int>& local_of);

/// Writes the step's line and, at an output time, its frame and history row. Under mpirun
/// (`several`) write() is a collective call every process makes, even the first after failing
/// to write steps.csv: that failure is raised after it. Throws OutputError.
void write_step_output(ResultsWriter& writer, const StepSnapshot& snap, bool several);

/// The model `velum pattern` and `velum seams` (`command`) read: the file, or the found form
/// (form.yaml) of a results folder, whose path goes to `model_file`; nullopt after saying why
/// on stderr (bad input).
std::optional<ModelInput> read_shape_model(const std::filesystem::path& input,
                                           const std::string& command,
                                           std::filesystem::path& model_file);

/// Debian's interpreter (the `python3` first on PATH may lack numpy).
inline constexpr const char* kPython = "/usr/bin/python3";
/// Runs kPython with `words` (and `environment` set in the child) for `command` (its name in
/// messages); the child's exit status, argparse's usage error (2) as bad input, kExitIo when
/// it cannot start (python_child.cpp).
int run_python(const std::string& command, std::vector<std::string> words,
               const std::vector<std::pair<std::string, std::string>>& environment = {});

/// Writes DIR/checkpoint.bin (restart.cpp). Throws OutputError.
void save_checkpoint(const ResultsWriter& writer, const ModelInput& input, int dofs,
                     Checkpoint run);
/// The checkpoint in DIR if it fits the model and the folder; otherwise nullopt, and why in
/// `errors` (bad input: nothing in DIR was touched).
std::optional<CheckpointFile> load_checkpoint(const std::filesystem::path& dir,
                                              const ModelInput& in, const MechanicalSystem& sys,
                                              std::vector<std::string>& errors);

/// A run stopped by SIGINT or SIGTERM (sig): status "interrupted", `reason`, exit 130 / 143.
void mark_interrupted(int sig, const std::string& reason, RunSummary& summary, RunOutcome& out);
/// Times the run (wall since `started`, CPU since `cpu_at_start`, threads) and writes
/// summary.json; false, with the outcome set to an I/O failure, when it cannot be written.
bool finish_summary(ResultsWriter& writer, RunSummary& summary,
                    std::chrono::steady_clock::time_point started, double cpu_at_start,
                    RunOutcome& out);

}  // namespace velum::run
