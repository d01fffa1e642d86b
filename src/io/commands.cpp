#include "velum/io/commands.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <map>

#include "velum/analysis/form_finding.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/assembly/model_piece.hpp"
#include "velum/config.hpp"
#include "velum/io/checkpoint.hpp"
#include "velum/io/form_model.hpp"
#include "velum/io/run_control.hpp"
#include "velum/solve/processes.hpp"

// Present when the BLAS behind SuiteSparse is OpenBLAS (Debian's alternatives), absent (null)
// with the reference BLAS.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace velum::io {
namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kUnitsNote =
    "units: the model's own (any consistent set); nothing is converted";

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  if (s < 60) return fmt::format("{:.0f}s", s);
  if (s < 3600) return fmt::format("{:.0f}m{:02.0f}s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f}h{:02.0f}m", std::floor(s / 3600), std::fmod(s / 60, 60));
}

/// Progress on stderr: a bar redrawn at most ten times a second on a terminal, otherwise
/// one line at the start and one at the end.
class Progress {
 public:
  Progress(bool quiet, double t0, double t_end)
      : quiet_(quiet),
        tty_(isatty(fileno(stderr)) != 0),
        t0_(t0),
        t_end_(t_end),
        start_(Clock::now()) {}

  void start(const std::string& what) {
    if (quiet_) return;
    if (!tty_) say(stderr, "velum: {} from t = {:.6g} to {:.6g}\n", what, t0_, t_end_);
  }
  void update(const AcceptedStep& s) {
    if (quiet_ || !tty_) return;
    const auto now = Clock::now();
    if (now - last_ < std::chrono::milliseconds(100) && s.t < t_end_) return;
    last_ = now;
    const double frac = std::clamp((s.t - t0_) / (t_end_ - t0_), 0.0, 1.0);
    const double elapsed = seconds_since(start_);
    const double eta = frac > 0 ? elapsed * (1 - frac) / frac : -1;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    say(stderr, "\r[{}{}] t = {:<10.4g} h = {:<9.3g} step {:<6d} newton {:<3d} ETA {:<8}",
        std::string(static_cast<size_t>(filled), '#'),
        std::string(static_cast<size_t>(kWidth - filled), '.'), s.t, s.h, s.step, s.iterations,
        duration_text(eta));
    std::fflush(stderr);
    drawn_ = true;
  }
  /// Ends the bar's line so that a message can follow.
  void end_line() {
    if (drawn_) say(stderr, "\n");
    drawn_ = false;
  }
  // A warning on its own line (the bar, if drawn, continues below it).
  void warn(const std::string& w) {
    if (drawn_) fmt::print(stderr, "\n");
    drawn_ = false;
    fmt::print(stderr, "warning: {}\n", w);
  }
  void finish(const TimeLoopResult& r) {
    if (quiet_) return;
    end_line();
    say(stderr,
        "velum: {} at t = {:.6g} after {} steps, {} Newton iterations ({} factorisations), {} "
        "cut-backs, {:.2f} s\n",
        r.completed ? "finished" : "stopped", r.t, r.steps, r.iterations, r.factorizations,
        r.cutbacks, seconds_since(start_));
  }

 private:
  bool quiet_, tty_;
  double t0_, t_end_;
  Clock::time_point start_, last_{};
  bool drawn_ = false;
};

/// Reads the model; on bad input prints every message and returns nullopt.
std::optional<ModelInput> load(const std::filesystem::path& file) {
  try {
    ModelInput in = read_model(file);
    for (const auto& w : in.warnings) say(stderr, "warning: {}\n", w);
    return in;
  } catch (const InputError& e) {
    for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
    say(stderr, "velum: {} error{} in {}\n", e.messages().size(),
        e.messages().size() == 1 ? "" : "s", file.string());
    return std::nullopt;
  }
}

// When output.checkpoint asks for one: every `steps` accepted steps, or at the first step at
// or past each multiple of `interval`; and at the end of the run (which can then be extended).
class CheckpointSchedule {
 public:
  CheckpointSchedule(const OutputSettings& out, const TimeLoopSettings& time)
      : steps_(out.checkpoint_steps),
        interval_(out.checkpoint_interval),
        end_(time.t_end),
        eps_(1e-9 * time.step) {}
  bool due(const AcceptedStep& st) {
    if (steps_ <= 0 && interval_ <= 0) return false;
    bool now = st.t >= end_ - eps_ || (steps_ > 0 && st.step % steps_ == 0);
    if (interval_ > 0) {
      const double k = std::floor((st.t + eps_) / interval_);
      now = now || k > last_k_;
      last_k_ = std::max(last_k_, k);
    }
    return now;
  }

 private:
  int steps_;
  double interval_, end_, eps_, last_k_ = 0;
};

void save_checkpoint(const ResultsWriter& writer, const std::filesystem::path& model, int dofs,
                     Checkpoint run) {
  const WriterPosition at = writer.position();
  write_checkpoint(writer.directory() / "checkpoint.bin",
                   CheckpointFile{.dofs = dofs,
                                  .model = model.filename().string(),
                                  .run = std::move(run),
                                  .history_bytes = at.history_bytes,
                                  .steps_bytes = at.steps_bytes,
                                  .frame_times = at.frame_times});
}

// The checkpoint in DIR, if it fits the model; otherwise a message and nullopt.
std::optional<CheckpointFile> load_checkpoint(const std::filesystem::path& dir,
                                              const ModelInput& in, const MechanicalSystem& sys) {
  try {
    CheckpointFile c = read_checkpoint(dir / "checkpoint.bin");
    if (c.dofs != sys.global_size() || c.run.state.u.size() != sys.global_size())
      throw std::runtime_error(
          fmt::format("{}: written by a model with {} equations ({}), this one has {}",
                      (dir / "checkpoint.bin").string(), c.dofs, c.model, sys.global_size()));
    if (in.analysis.path.method != PathSettings::Method::kLoadControl)
      throw std::runtime_error("--restart: path following (analysis.path) has no checkpoints");
    return c;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return std::nullopt;
  }
}

std::map<std::string, int> elements_per_type(const Model& m) {
  std::map<std::string, int> out;
  for (const auto& b : m.blocks) out[std::string(b->type_name())] += b->size();
  return out;
}

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\')
      o += '\\', o += c;
    else if (static_cast<unsigned char>(c) < 0x20)
      o += fmt::format("\\u{:04x}", static_cast<int>(c));
    else
      o += c;
  }
  return o;
}

/// Marks DIR as holding a run in progress and removes what a previous run left that the new
/// one might not overwrite (its frames and their index).
void begin_results(const std::filesystem::path& dir, const std::filesystem::path& model) {
  write_file_atomically(dir / "summary.json",
                        fmt::format("{{\n  \"status\": \"running\",\n  \"model\": \"{}\",\n  "
                                    "\"pid\": {}\n}}\n",
                                    json_escape(model.string()), getpid()));
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

// Under mpirun: the model cut down to this process's piece (share_model), and the history's
// nodes renumbered to the piece's (-1, or left out of a reaction's list: another process's).
void share_out(ModelInput& input) {
  const std::vector<int> local_of = share_model(input.model, input.analysis.partition);
  for (HistoryEntry& h : input.output.history) {
    if (h.node >= 0) h.node = local_of[static_cast<size_t>(h.node)];
    std::vector<int> nodes;
    for (int n : h.nodes)
      if (const int l = local_of[static_cast<size_t>(n)]; l >= 0) nodes.push_back(l);
    h.nodes = std::move(nodes);
  }
  if (PathSettings& path = input.analysis.path; path.node >= 0)
    path.node = local_of[static_cast<size_t>(path.node)];
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
    return false;
  }
  return true;
}

int check_command(const std::filesystem::path& file) {
  say(stdout, "velum {} check: {}\n{}\n", VELUM_VERSION, file.string(), kUnitsNote);
  auto in = load(file);
  if (!in) return kExitBadInput;
  const Model& m = in->model;
  int dofs = 0;
  try {
    dofs = DofMap(m).num_equations();
  } catch (const std::exception& e) {
    say(stderr, "error: {}: {}\n", file.string(), e.what());
    return kExitBadInput;
  }
  if (!in->title.empty()) say(stdout, "title:      {}\n", in->title);
  say(stdout, "nodes:      {}\n", m.num_nodes());
  std::string per_type;
  for (const auto& [t, n] : elements_per_type(m)) per_type += fmt::format(" {} {}", t, n);
  say(stdout, "elements:   {} ({})\n", m.num_elements(),
      per_type.empty() ? "" : per_type.substr(1));
  say(stdout, "blocks:     {}\n", m.blocks.size());
  say(stdout, "dofs:       {} equations ({} fixed or prescribed components)\n", dofs,
      3 * m.num_nodes() - dofs);
  std::string mats;
  for (const auto& mt : in->materials)
    mats += fmt::format("{}{} ({})", mats.empty() ? "" : ", ", mt.name, mt.type);
  say(stdout, "materials:  {}\n", mats);
  say(stdout, "loads:      {}; {} point masses\n", load_counts(m.loads), m.masses.size());
  for (const std::string& line : load_summaries(m.loads)) say(stdout, "{}\n", line);
  say(stdout, "boundary:   {} fixed, {} prescribed, {} symmetry\n", m.fixed.size(),
      m.prescribed.size(), m.symmetry.size());
  const auto& a = in->analysis;
  say(stdout, "analysis:   {}, {}, t_end {:.6g}, step {:.6g} (min {:.6g}{})\n", a.type_name(),
      a.type == AnalysisSettings::Type::kStatic        ? "load stepping"
      : a.type == AnalysisSettings::Type::kRelaxation  ? "kinetic damping, then Newton"
      : a.type == AnalysisSettings::Type::kFormFinding ? "updated reference"
                                                       : a.scheme,
      a.time.t_end, a.time.step, a.time.min_step, a.time.adaptive ? ", adaptive" : "");
  say(stdout, "{}", describe_steps(*in));
  say(stdout, "output:     {} every {:.6g}, {} history column{}{}\n", in->output.directory.string(),
      in->output.interval, in->output.history.size(), in->output.history.size() == 1 ? "" : "s",
      in->output.fields ? ", fields" : "");
  say(stdout, "velum: {} is valid\n", file.string());
  return kExitOk;
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

RunOutcome run_model(ModelInput& input, const RunControls& controls) {
  RunOutcome out;
  const double cpu_at_start = cpu_seconds();
  // Several processes (docs/parallel.md): each holds the model and the state and runs the same
  // loop; the first alone writes (folder, lock, results) and speaks on the console.
  const bool writes = processes::rank() == 0, several = processes::count() > 1;
  RunControls opt = controls;
  if (!writes) opt.quiet = true;
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  // OpenBLAS (behind CHOLMOD and UMFPACK) keeps its own busy-waiting threads: with more threads
  // than cores they spin against ours (a 2,000-DOF run spent 14 s in the kernel, 0.1 s with
  // one BLAS thread). Give BLAS the same count as OpenMP.
  if (openblas_set_num_threads) openblas_set_num_threads(omp_get_max_threads());
  if (opt.output) input.output.directory = *opt.output;
  out.directory = input.output.directory;
  if (!input.steps.empty()) return run_staged(input, opt);  // staged_run.cpp

  if (several && input.analysis.solver != SolverKind::kPetsc) {
    out.status = kExitBadInput;
    out.errors.push_back(
        fmt::format("{}: analysis.linear_solver: a run on {} processes needs linear_solver: petsc",
                    input.file.string(), processes::count()));
    return out;
  }
  const int all_nodes = input.model.num_nodes();
  if (PathSettings& path = input.analysis.path;
      path.method == PathSettings::Method::kDisplacement) {
    // Its equation in the whole model's numbering (the node may be another process's).
    path.equation = DofMap(input.model).global_equation(path.node, path.component);
    if (path.equation < 0) {
      out.status = kExitBadInput;
      out.errors.push_back(fmt::format(
          "{}: analysis.path: node {} {} is fixed, prescribed or normal to a symmetry plane: "
          "displacement control needs a free component",
          input.file.string(), input.model.node_ids[path.node], "xyz"[path.component]));
      return out;
    }
  }
  std::unique_ptr<MechanicalSystem> system;
  try {
    // Several processes: each keeps its piece of the model only (its elements' section data,
    // the nodes it holds), so that the memory per process falls with the processes.
    if (several) share_out(input);
    system = std::make_unique<MechanicalSystem>(input.model);
  } catch (const std::exception& e) {
    out.status = kExitBadInput;
    out.errors.push_back(fmt::format("{}: {}", input.file.string(), e.what()));
    return out;
  }
  std::optional<CheckpointFile> resume;
  if (opt.restart) {
    input.output.directory = *opt.restart;
    out.directory = *opt.restart;
    if (!(resume = load_checkpoint(*opt.restart, input, *system))) {
      out.status = kExitBadInput;
      return out;
    }
  }
  const std::filesystem::path dir = input.output.directory;
  std::optional<OutputLock> lock;
  std::unique_ptr<ResultsWriter> writer;
  if (writes && !open_results(input, *system, dir, resume, out, lock, writer)) {
    processes::all(false);
    return out;
  }
  if (!processes::all(true)) {  // the first process could not open its results
    out.status = kExitIo;
    return out;
  }
  // Another process's writer: its part of the history's values and its pieces of the frames.
  if (!writes) try {
      std::optional<WriterPosition> at;
      if (resume) at = WriterPosition{.frame_times = resume->frame_times};
      writer = std::make_unique<ResultsWriter>(input, *system, dir, at ? &*at : nullptr);
    } catch (const OutputError& e) {
      out.status = kExitIo;
      out.errors.push_back(e.what());
      return out;
    }
  CheckpointSchedule checkpoints(input.output, input.analysis.time);
  AnalysisSettings settings = input.analysis;
  settings.time.output_interval = input.output.interval;
  if (!opt.quiet)
    say(stderr, "velum: {} nodes, {} elements, {} equations; results in {}\n", all_nodes,
        input.model.num_elements(), system->global_size(), input.output.directory.string());
  if (several) {  // the partition of the elements (docs/parallel.md)
    const auto own = processes::gather(static_cast<double>(system->assembler().own_elements()));
    const Assembler& a = system->assembler();
    if (!opt.quiet && !a.partition_note().empty())
      say(stderr, "velum: analysis.partition: scotch not used ({}); elements shared by rows\n",
          a.partition_note());
    if (!opt.quiet) {
      std::string list;
      for (double n : own) list += fmt::format("{}{}", list.empty() ? "" : ", ", n);
      say(stderr, "velum: {} processes compute {} elements each ({} partition, {} nodes shared)\n",
          own.size(), list, a.partition() == ElementPartition::kScotch ? "scotch" : "rows",
          a.shared_nodes());
    }
  }

  Progress progress(opt.quiet, settings.time.t0, settings.time.t_end);
  progress.start(
      (settings.type == AnalysisSettings::Type::kStatic       ? std::string("static load stepping")
       : settings.type == AnalysisSettings::Type::kRelaxation ? std::string("dynamic relaxation")
       : settings.type == AnalysisSettings::Type::kFormFinding
           ? std::string("form finding (updated reference)")
           : "dynamic run (" + settings.scheme + ")") +
      (resume ? fmt::format(", restarted at t = {:.6g}", resume->run.loop.t) : ""));
  AnalysisResult result;
  std::exception_ptr output_failure;
  RunSummary& summary = out.summary;
  summary.elements = input.model.num_elements();
  // Per process figures for summary.json (a collective call: every process, once).
  const auto gather_processes = [&] {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);  // ru_maxrss: kibibytes on Linux
    summary.process_elements =
        processes::gather(static_cast<double>(system->assembler().own_elements()));
    summary.partition =
        system->assembler().partition() == ElementPartition::kScotch ? "scotch" : "rows";
    summary.shared_nodes = system->assembler().shared_nodes();
    summary.process_cpu_seconds = processes::gather(cpu_seconds() - cpu_at_start);
    summary.process_memory_mb = processes::gather(static_cast<double>(usage.ru_maxrss) / 1024.0);
  };
  summary.dofs = static_cast<int>(system->global_size());
  try {
    const auto observe = [&](const StepSnapshot& snap) {
      bool written = true;
      if (writer) try {
          // Under mpirun write() is a collective call: every process makes it, even the first
          // after failing to write steps.csv (the failure is raised after it).
          std::exception_ptr steps_failure;
          try {
            writer->write_step(snap.step);
          } catch (const OutputError&) {
            if (!several) throw;
            steps_failure = std::current_exception();
          }
          if (snap.step.output_time) writer->write(snap);
          if (steps_failure) std::rethrow_exception(steps_failure);
          // Made on every process (the state is gathered to the first), written by the first.
          if (snap.checkpoint && checkpoints.due(snap.step)) {
            Checkpoint c = (*snap.checkpoint)();
            if (writes)
              save_checkpoint(*writer, input.file, static_cast<int>(system->global_size()),
                              std::move(c));
          }
        } catch (const OutputError&) {
          if (!several) throw;
          output_failure = std::current_exception();  // the others stop with this one
          written = false;
        }
      summary.final_time = snap.step.t;
      progress.update(snap.step);
      // SIGINT, SIGTERM (under run_command's InterruptGuard): stop after this step; under
      // mpirun, every process stops after the same step.
      const bool go = written && (!opt.on_step || opt.on_step(snap.step)) &&
                      InterruptGuard::signal_received() == 0;
      return several ? processes::all(go) : go;
    };
    const auto warn = [&](const std::string& w) { progress.warn(w); };
    if (settings.type == AnalysisSettings::Type::kFormFinding) {
      FormFindingReport found;
      result = run_form_finding(input.model, *system, settings, observe, warn, &found);
      summary.form_residual = found.residual;
      summary.form_updates = found.updates;
      if (result.loop.completed && writes) write_form_model(input, found.shape, dir / "form.yaml");
    } else {
      result =
          run_analysis(*system, settings, observe, warn, nullptr, resume ? &resume->run : nullptr);
    }
    if (output_failure) std::rethrow_exception(output_failure);
    progress.finish(result.loop);
    summary.converged = result.loop.completed;
    summary.reason = result.loop.reason;
    summary.steps = result.loop.steps;
    summary.newton_iterations = result.loop.iterations;
    summary.factorizations = result.loop.factorizations;
    summary.final_time = result.loop.completed ? result.loop.t : summary.final_time;
    summary.energy = result.energy;
    summary.integrator = result.integrator;
    summary.solver = result.solver;
    summary.dofs = result.dofs;
    out.stopped = result.loop.stopped;
    if (out.stopped && summary.reason.empty())
      summary.reason = fmt::format("stopped by the caller at t = {:.6g}", summary.final_time);
    if (!result.loop.completed) out.status = kExitSolveFailed;
    summary.warnings = result.warnings;
    if (const int sig = InterruptGuard::signal_received(); sig && !result.loop.completed)
      mark_interrupted(
          sig, fmt::format("after step {} (t = {:.6g})", result.loop.steps, summary.final_time),
          summary, out);
  } catch (const OutputError& e) {
    if (several) gather_processes();  // the first process alone fails here: the others gather
    progress.end_line();
    out.status = kExitIo;
    out.errors.push_back(e.what());
    return out;
  } catch (const std::exception& e) {
    summary.converged = false;
    summary.reason = e.what();
    out.status = kExitSolveFailed;
  }
  if (several) gather_processes();
  if (!writes || !finish_summary(*writer, summary, opt.started, cpu_at_start, out)) return out;
  if (out.status == kExitSolveFailed) {
    out.errors.push_back(
        fmt::format("the solve failed at t = {:.6g} (step {}, last output kept in {}): {}",
                    result.loop.t, result.loop.steps + 1, input.output.directory.string(),
                    summary.reason.empty() ? "unknown reason" : summary.reason));
    return out;
  }
  if (!opt.quiet && !summary.warnings.empty())
    fmt::print(stderr, "velum: {} warning{} (in summary.json)\n", summary.warnings.size(),
               summary.warnings.size() == 1 ? "" : "s");
  if (!opt.quiet)
    say(stderr,
        "velum: converged; energy: kinetic {:.6g}, strain {:.6g}, external work {:.6g}, "
        "damping {:.6g}\n",
        summary.energy.kinetic, summary.energy.strain, summary.energy.external_work,
        summary.energy.damping);
  return out;
}

int run_command(const RunOptions& opt) {
  RunControls controls;
  const bool speaks = processes::rank() == 0;  // under mpirun, the first process only
  if (!opt.quiet && speaks)
    say(stderr, "velum {} run: {}\n{}\n", VELUM_VERSION, opt.model.string(), kUnitsNote);
  controls.output = opt.output;
  controls.threads = opt.threads;
  controls.quiet = opt.quiet;
  controls.restart = opt.restart;
  InterruptGuard interrupts;  // SIGINT, SIGTERM: finish the current step, then stop
  auto in = load(opt.model);
  if (!in) return kExitBadInput;
  if (const int sig = InterruptGuard::signal_received())  // nothing written yet
    return sig == SIGINT ? kExitInterrupted : kExitTerminated;
  const RunOutcome out = run_model(*in, controls);
  if (!speaks) {  // the first process speaks; another one only of its own output's failure
    if (out.status == kExitIo)
      for (const auto& e : out.errors)
        say(stderr, "error (process {}): {}\n", processes::rank(), e);
    return out.status;
  }
  for (const auto& e : out.errors) say(stderr, "error: {}\n", e);
  if (out.status == kExitInterrupted || out.status == kExitTerminated)
    say(stderr, "velum: {}; results up to there are in {}\n", out.summary.reason,
        out.directory.string());
  return out.status;
}

}  // namespace velum::io
