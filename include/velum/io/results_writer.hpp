// Writes the results of a run into a directory (docs/model-format.md): history.csv (one row per
// output time, flushed), steps.csv (one row per accepted step, flushed), results.pvd +
// frames/frame_NNNNN.vtu (VTK XML, appended raw binary, each written to a temporary file and
// renamed) and summary.json. Values are in the user's units; angles in the fields are in degrees.
#pragma once

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/io/frame_fields.hpp"
#include "velum/io/frame_writer.hpp"
#include "velum/io/model_reader.hpp"

namespace velum::io {

/// The output directory or a file in it cannot be written.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One analysis step of a staged run, as summary.json's analysis_steps lists it.
struct StepSummary {
  std::string name, type;               ///< analysis.type of the step
  std::string status;                   ///< converged | failed | not run
  double start_time = 0, end_time = 0;  ///< total time (end: where it stopped)
  int steps = 0, newton_iterations = 0;
  std::string integrator, reason;
  int form_updates = -1;  ///< form finding: reference updates
  double form_residual = 0;
  double external_work = 0;  ///< the work of loads and prescribed motions in this step
};

struct RunSummary {
  bool converged = false;
  int steps = 0, newton_iterations = 0, factorizations = 0;
  double wall_seconds = 0, final_time = 0;
  int dofs = 0, elements = 0;
  Energies energy;
  std::string reason, integrator, solver;
  std::vector<std::string> warnings;  ///< what a user must know about a normal end
  std::string status;      ///< when set ("interrupted"), replaces "converged" or "failed"
  double cpu_seconds = 0;  ///< CPU time (user + system, all threads) of the run
  int threads = 0;         ///< OpenMP threads the run used
  /// Under mpirun (more than one entry): per process, in rank order, the elements it
  /// computed, its CPU seconds and its peak memory (MB).
  std::vector<double> process_elements, process_cpu_seconds, process_memory_mb;
  /// Under mpirun: per process, the processes it exchanges shared nodes with.
  std::vector<double> process_neighbours;
  std::string partition;     ///< under mpirun: rows | scotch (the one used)
  long shared_nodes = 0;     ///< under mpirun: nodes held by elements of several processes
  int form_updates = -1;     ///< form finding: reference updates (-1: not form finding)
  double form_residual = 0;  ///< form finding: residual / force scale on the found shape
  std::vector<StepSummary> analysis_steps;  ///< a staged model's steps (empty otherwise)
  /// Central difference: its step and mass scaling ("explicit_step"; estimates 0: none).
  ExplicitStepReport explicit_step;
  double safety = 0, target_step = 0;
};

/// The largest (or smallest) value of a result over the output times so far, where and when.
struct Extreme {
  bool found = false;
  double value = 0, time = 0;
  long id = 0;  ///< the user's element or node id
  void offer(double v, long at, double t, bool larger) {
    if (std::isnan(v) || (found && (larger ? v <= value : v >= value))) return;
    found = true, value = v, id = at, time = t;
  }
};

/// Where the results files stood (for a checkpoint, and a restart that goes on from there).
struct WriterPosition {
  long history_bytes = 0, steps_bytes = 0;
  std::vector<double> frame_times;
};

class ResultsWriter {
 public:
  /// Creates the directory (and frames/ when fields are on) and history.csv. `system` is the
  /// one being solved (reactions re-evaluate its external forces). With `resume`, the files
  /// already there are cut back to that position and continued. Throws OutputError.
  /// Under mpirun the first process writes everything; the others (constructed after the
  /// first has made the folder) write only their pieces of the frames (frame_writer.hpp).
  ResultsWriter(const ModelInput& input, MechanicalSystem& system, std::filesystem::path directory,
                const WriterPosition* resume = nullptr);
  /// The position now (files flushed).
  WriterPosition position() const;
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter&) = delete;
  ResultsWriter& operator=(const ResultsWriter&) = delete;

  /// Writes the history row and, with fields on, a frame for an output time; updates the
  /// extremes of summary.json.
  void write(const StepSnapshot& snap);
  /// One history row (no frame). Under mpirun a collective call, as write().
  void write_history(const StepSnapshot& snap);
  /// One row of steps.csv (iterations and the residual norm before each solve, and after the
  /// last, of an accepted step; space-separated), flushed.
  void write_step(const AcceptedStep& step);
  void write_summary(const RunSummary& s);

  /// A staged run: the rows and frames that follow belong to analysis step `number`
  /// (1-based), solved by `system` on the model now in the ModelInput given at construction.
  void begin_analysis_step(int number, MechanicalSystem& system) {
    analysis_step_ = number;
    system_ = &system;
  }

  const std::filesystem::path& directory() const { return dir_; }
  int frames() const { return static_cast<int>(frame_times_.size()); }

 private:
  std::string accounts_;  ///< the loads' accounts (LoadTerm::account_json) at the last output
  std::string contact_accounts_;  ///< the same of the contacts (a list of their own)
  /// The loads' point fields of the frame being written (contact_pressure, contact_gap).
  std::vector<std::pair<std::string, std::vector<double>>> node_fields_;
  /// This process's part of history entry h (history_row sums the parts; collective for gas).
  double history_value(const HistoryEntry& h, const StepSnapshot& snap, const NodePositions& U,
                       const NodePositions& V, const NodePositions& x, const NodePositions& R);
  /// The history values at positions U, V, x and reactions R (when needs_reactions()),
  /// summed over the processes (the same bits on every one). A collective call.
  std::vector<double> history_row(const StepSnapshot& snap, const NodePositions& U,
                                  const NodePositions& V, const NodePositions& x,
                                  const NodePositions& R);
  void write_history_row(const StepSnapshot& snap, const std::vector<double>& values);
  bool needs_reactions() const;
  /// Internal minus external force at the supported components (zero elsewhere), 3 x nodes:
  /// complete at the nodes of this process's elements (and the nodes it keeps). Collective.
  NodePositions reactions(const StepSnapshot& snap, const NodePositions& x) const;
  void write_frame(double t, const NodePositions& U, const NodePositions& V, const NodePositions& R,
                   const FrameFields& f, const std::vector<std::vector<double>>& averaged,
                   const std::vector<double>& gas);
  /// The summary's extremes over the cells `own` lists, reduced to the first (collective).
  void update_extremes(double t, const NodePositions& U, const FrameFields& f,
                       const std::vector<std::vector<int>>& own);
  void write_legend() const;
  void write_pvd();

  const ModelInput& input_;
  MechanicalSystem* system_;
  bool records_;  // history, steps, the .pvd series, extremes: one process, or the first
  int analysis_step_ = 0;
  std::filesystem::path dir_;
  std::FILE* history_ = nullptr;
  std::FILE* steps_ = nullptr;
  std::vector<double> frame_times_;
  CellLabels labels_;
  std::optional<FrameWriter> frames_;  // with fields on
  Extreme max_stress_, max_force_per_length_, max_displacement_, min_cable_force_, max_cable_force_;
};

/// Writes `text` to `path` through a temporary file and a rename. Throws OutputError.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace velum::io
