#include "velum/run/run_model.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <map>

#include "progress.hpp"
#include "run_parts.hpp"
#include "velum/analysis/analysis.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/assembly/share_model.hpp"
#include "velum/config.hpp"
#include "velum/io/checkpoint.hpp"
#include "velum/io/form_model.hpp"
#include "velum/io/run_control.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/solve/blas_kernels.hpp"

// Present when the BLAS behind SuiteSparse is OpenBLAS (Debian's alternatives), absent (null)
// with the reference BLAS.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace velum::run {
namespace {

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

// Under mpirun: the model cut down to this process's piece (share_model), and the history's
// nodes renumbered to the piece's (-1, or left out of a reaction's list: another process's).
void share_out(ModelInput& input) {
  const std::vector<int> local_of = share_model(input.model, input.analysis.partition);
  renumber_history(input.output.history, local_of);
  if (PathSettings& path = input.analysis.path; path.node >= 0)
    path.node = local_of[static_cast<size_t>(path.node)];
}

}  // namespace

void renumber_history(std::vector<HistoryEntry>& history, const std::vector<int>& local_of) {
  for (HistoryEntry& h : history) {
    if (h.node >= 0) h.node = local_of[static_cast<size_t>(h.node)];
    std::vector<int> nodes;
    for (int n : h.nodes)
      if (const int l = local_of[static_cast<size_t>(n)]; l >= 0) nodes.push_back(l);
    h.nodes = std::move(nodes);
  }
}

void write_step_output(ResultsWriter& writer, const StepSnapshot& snap, bool several) {
  std::exception_ptr steps_failure;
  try {
    writer.write_step(snap.step);
  } catch (const OutputError&) {
    if (!several) throw;
    steps_failure = std::current_exception();
  }
  if (snap.step.output_time) writer.write(snap);
  if (steps_failure) std::rethrow_exception(steps_failure);
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
  // than cores they spin against ours (a small model's run spent most of its time in the
  // kernel). Give BLAS the same count as OpenMP.
  if (openblas_set_num_threads) openblas_set_num_threads(omp_get_max_threads());
  // On one thread OpenBLAS never hands work to its workers, which it started when it was
  // loaded and which spin (sched_yield) for 2^28 clock ticks (about 0.1 s) before they sleep:
  // CPU of another core that a one-thread run would pay for. Ended here.
  if (omp_get_max_threads() == 1) stop_idle_blas_threads();
  if (opt.output) input.output.directory = *opt.output;
  out.directory = input.output.directory;
  if (opt.restart && input.model.piece) {  // (the same decision on every process)
    out.status = kExitBadInput;
    out.errors.push_back(fmt::format(
        "{}: mesh.parts: --restart is not available for a model read in parts yet: run the "
        "model with its whole mesh (mesh.file) to restart it",
        input.file.string()));
    return out;
  }
  if (!input.steps.empty()) return run_staged(input, opt);  // staged_run.cpp

  if (several && input.analysis.solver != SolverKind::kPetsc) {
    out.status = kExitBadInput;
    out.errors.push_back(
        fmt::format("{}: analysis.linear_solver: a run on {} processes needs linear_solver: petsc",
                    input.file.string(), processes::count()));
    return out;
  }
  const int all_nodes =  // (a model read in parts: the whole model's)
      input.model.piece ? input.model.piece->global_nodes : input.model.num_nodes();
  // Displacement control: its equation in the whole model's numbering (the node may be
  // another process's once the model is shared out).
  // (A model read in parts has it from the split.)
  if (PathSettings& path = input.analysis.path;
      path.method == PathSettings::Method::kDisplacement && !input.model.piece) {
    if (const std::string why = resolve_path_equation(path, input.model, DofMap(input.model));
        !why.empty()) {
      out.status = kExitBadInput;
      out.errors.push_back(fmt::format("{}: {}", input.file.string(), why));
      return out;
    }
  }
  std::unique_ptr<MechanicalSystem> system;
  try {
    // Several processes: each keeps its piece of the model only (its elements' section data,
    // the nodes it holds), so that the memory per process falls with the processes.
    // A model read in parts (mesh.parts) is a piece already.
    if (several && !input.model.piece) share_out(input);
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
    if (!(resume = load_checkpoint(*opt.restart, input, *system, out.errors))) {
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
  // SIGINT, SIGTERM inside the loops that may run long (Newton, relaxation, path steps, form
  // finding): under mpirun every process asks at the same points, and all stop together.
  settings.newton.interrupted = [several] {
    const bool mine = InterruptGuard::signal_received() != 0;
    return several ? !processes::all(!mine) : mine;
  };
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
  progress.start(settings.run_name() +
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
    summary.process_neighbours =
        processes::gather(static_cast<double>(system->assembler().neighbours()));
    summary.process_cpu_seconds = processes::gather(cpu_seconds() - cpu_at_start);
    summary.process_memory_mb = processes::gather(static_cast<double>(usage.ru_maxrss) / 1024.0);
  };
  summary.dofs = static_cast<int>(system->global_size());
  // Under mpirun the processes agree after a step whether to go on (a signal, an output
  // error on the first process): every step of an implicit run; an explicit run's steps are
  // short, so at its checks (every kExplicitCheckInterval steps) and output times, a process
  // that would stop in between keeping on until then.
  const bool explicit_steps = settings.explicit_steps();
  bool stop_at_vote = false;
  try {
    const auto observe = [&](const StepSnapshot& snap) {
      bool written = true;
      if (writer) try {
          write_step_output(*writer, snap, several);
          // Made on every process (the state is gathered to the first), written by the first.
          if (snap.checkpoint && checkpoints.due(snap.step)) {
            Checkpoint c = (*snap.checkpoint)();
            if (writes)
              save_checkpoint(*writer, input, static_cast<int>(system->global_size()),
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
      bool go = written && (!opt.on_step || opt.on_step(snap.step)) &&
                InterruptGuard::signal_received() == 0;
      if (!several) return go;
      if (explicit_steps && !snap.step.output_time &&
          snap.step.step % kExplicitCheckInterval != 0) {
        stop_at_vote = stop_at_vote || !go;
        return true;
      }
      go = processes::all(go && !stop_at_vote);
      stop_at_vote = false;
      return go;
    };
    const auto warn = [&](const std::string& w) { progress.warn(w); };
    FormFindingReport found;
    result = run_analysis(input.model, *system, settings,
                          {.step = observe, .warning = warn, .form = &found},
                          {.resume = resume ? &resume->run : nullptr});
    if (settings.type == AnalysisSettings::Type::kFormFinding) {
      summary.form_residual = found.residual;
      summary.form_updates = found.updates;
      if (result.loop.completed && writes) write_form_model(input, found.shape, dir / "form.yaml");
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
    summary.explicit_step = result.explicit_step;
    summary.safety = settings.explicit_step.safety;
    summary.target_step = settings.explicit_step.target_step;
    summary.solver = result.solver;
    summary.dofs = result.dofs;
    out.stopped = result.loop.stopped;
    if (out.stopped && summary.reason.empty())
      summary.reason = fmt::format("stopped by the caller at t = {:.6g}", summary.final_time);
    if (!result.loop.completed) out.status = kExitSolveFailed;
    summary.warnings = input.warnings;  // the reader's (not printed under --quiet), the run's
    summary.warnings.insert(summary.warnings.end(), result.warnings.begin(), result.warnings.end());
    if (const int sig = InterruptGuard::signal_received(); sig && !result.loop.completed)
      mark_interrupted(
          sig, fmt::format("after step {} (t = {:.6g})", result.loop.steps, summary.final_time),
          summary, out);
  } catch (const OutputError& e) {
    if (several) gather_processes();  // the first process alone fails here: the others gather
    progress.end_line();
    out.status = kExitIo;
    out.errors.push_back(e.what());
    // summary.json says so (where it can still be written), not "running".
    summary.converged = false;
    summary.reason = fmt::format("the results could not be written: {}", e.what());
    if (writes && writer) finish_summary(*writer, summary, opt.started, cpu_at_start, out);
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
  if (out.status == kExitInterrupted || out.status == kExitTerminated) return out;
  if (!opt.quiet && !summary.warnings.empty())
    say(stderr, "velum: {} warning{} (in summary.json)\n", summary.warnings.size(),
        summary.warnings.size() == 1 ? "" : "s");
  if (!opt.quiet)
    say(stderr,
        "velum: converged; energy: kinetic {:.6g}, strain {:.6g}, external work {:.6g}, "
        "damping {:.6g}\n",
        summary.energy.kinetic, summary.energy.strain, summary.energy.external_work,
        summary.energy.damping);
  return out;
}

}  // namespace velum::run
