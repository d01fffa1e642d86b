// The results folder of a run: created, locked, marked "running" before anything of a previous
// run is touched, and closed by summary.json.
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include "progress.hpp"
#include "run_parts.hpp"
#include "velum/io/json_text.hpp"

namespace velum::run {
namespace {

/// Marks DIR as holding a run in progress and removes what a previous run left that the new
/// one might not overwrite (its frames and their index).
void begin_results(const std::filesystem::path& dir, const std::filesystem::path& model) {
  write_file_atomically(dir / "summary.json",
                        fmt::format("{{\n  \"status\": \"running\",\n  \"model\": {},\n  "
                                    "\"pid\": {}\n}}\n",
                                    json_string(model.string()), getpid()));
  std::error_code ec;
  std::filesystem::remove(dir / "results.pvd", ec);
  if (std::filesystem::is_directory(dir / "frames", ec))
    for (const auto& f : std::filesystem::directory_iterator(dir / "frames", ec)) {
      const std::string name = f.path().filename().string();
      if (name.rfind("frame_", 0) != 0) continue;
      if (f.path().extension() == ".vtu" || f.path().extension() == ".pvtu")
        std::filesystem::remove(f.path(), ec);
      else if (f.is_directory(ec))  // the pieces of a run on several processes
        std::filesystem::remove_all(f.path(), ec);
    }
}

}  // namespace

// The output folder, its lock and the results writer (the first process's, under mpirun).
// One run per folder: the lock first, then "running" in summary.json before anything of a
// previous run is touched, so that no moment shows its "converged" beside a new history.
bool open_results(const ModelInput& input, MechanicalSystem& system,
                  const std::filesystem::path& dir, const std::optional<CheckpointFile>& resume,
                  RunOutcome& out, std::optional<OutputLock>& lock,
                  std::unique_ptr<ResultsWriter>& writer) {
  {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
      out.status = kExitIo;
      out.errors.push_back(fmt::format("cannot create the output directory {}: {}", dir.string(),
                                       ec ? ec.message() : "not a directory"));
      return false;
    }
  }
  lock.emplace(dir);
  if (!lock->held()) {
    out.status = kExitIo;
    out.errors.push_back(
        fmt::format("{}: {}; wait for it to end or choose another output directory", dir.string(),
                    lock->why_not()));
    return false;
  }
  try {
    WriterPosition at;
    if (resume)  // a restart goes on with the files as its checkpoint left them
      at = {.history_bytes = resume->history_bytes,
            .steps_bytes = resume->steps_bytes,
            .frame_times = resume->frame_times};
    else
      begin_results(dir, input.file);
    writer = std::make_unique<ResultsWriter>(input, system, dir, resume ? &at : nullptr);
  } catch (const OutputError& e) {
    out.status = kExitIo;
    out.errors.push_back(e.what());
    // Not "running" once the run is over (where summary.json can still be written).
    try {
      write_file_atomically(
          dir / "summary.json",
          fmt::format("{{\n  \"status\": \"failed\",\n  \"reason\": {},\n  \"model\": {}\n}}\n",
                      json_string(fmt::format("the results could not be written: {}", e.what())),
                      json_string(input.file.string())));
    } catch (const OutputError&) {
    }
    return false;
  }
  return true;
}

void mark_interrupted(int sig, const std::string& reason, RunSummary& summary, RunOutcome& out) {
  summary.status = "interrupted";
  summary.reason =
      fmt::format("interrupted by {} {}", sig == SIGINT ? "SIGINT" : "SIGTERM", reason);
  out.status = sig == SIGINT ? kExitInterrupted : kExitTerminated;
}

bool finish_summary(ResultsWriter& writer, RunSummary& summary, Clock::time_point started,
                    double cpu_at_start, RunOutcome& out) {
  summary.wall_seconds = seconds_since(started);
  summary.cpu_seconds = cpu_seconds() - cpu_at_start;
  summary.threads = omp_get_max_threads();
  try {
    writer.write_summary(summary);
  } catch (const OutputError& e) {
    out.status = kExitIo;
    out.errors.push_back(e.what());
    return false;
  }
  return true;
}

}  // namespace velum::run
