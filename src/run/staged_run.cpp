// `velum run` on a model with steps (analysis/stages.hpp): one results folder for all steps,
// history.csv and steps.csv with an analysis_step column, one frame series, and summary.json
// with the totals at the top level and each step in analysis_steps.
#include <fmt/format.h>

#include <algorithm>

#include "run_parts.hpp"
#include "velum/assembly/share_model.hpp"
#include "velum/io/run_control.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::run {
namespace {

// Under mpirun: the steps' models (prepared whole) and the first model cut to one piece each,
// the same elements and nodes in every step; the history's nodes renumbered to the piece's.
void share_steps(ModelInput& input) {
  MeshSharing sharing;
  add_equation_owners(sharing, input.model);
  for (const AnalysisStep& s : input.steps) add_equation_owners(sharing, s.model);
  const std::vector<int> local_of = share_model(input.model, input.analysis.partition, sharing);
  for (AnalysisStep& s : input.steps) share_model(s.model, input.analysis.partition, sharing);
  renumber_history(input.output.history, local_of);
}

}  // namespace

RunOutcome run_staged(ModelInput& input, const RunControls& opt) {
  RunOutcome out;
  const double cpu_at_start = cpu_seconds();
  out.directory = input.output.directory;
  auto refuse = [&](std::string why) {
    out.status = kExitBadInput;
    out.errors.push_back(fmt::format("{}: {}", input.file.string(), why));
    return out;
  };
  if (opt.restart)
    return refuse(
        "--restart: a model with steps writes no checkpoints and cannot be restarted; run it "
        "again from the start");
  // Several processes (docs/parallel.md): each holds its piece of every step's model, the
  // first alone writes and speaks.
  const bool several = processes::count() > 1, writes = processes::rank() == 0;
  if (several)
    for (const AnalysisStep& s : input.steps)
      if (s.analysis.solver != SolverKind::kPetsc)
        return refuse(fmt::format(
            "step '{}': analysis.linear_solver: a run on {} processes needs linear_solver: petsc",
            s.name, processes::count()));
  const PreparedSteps prepared = prepare_steps(input.steps);
  const int all_nodes =  // (a model read in parts: the whole model's)
      input.model.piece ? input.model.piece->global_nodes : input.model.num_nodes();
  std::optional<OutputLock> lock;
  std::unique_ptr<ResultsWriter> writer;
  {
    std::unique_ptr<MechanicalSystem> first;  // the writer's until the first step begins
    try {
      if (several && !input.model.piece) share_steps(input);  // (mesh.parts: pieces already)
      first = std::make_unique<MechanicalSystem>(input.model);
    } catch (const std::exception& e) {
      return refuse(e.what());
    }
    if (writes &&
        !open_results(input, *first, input.output.directory, std::nullopt, out, lock, writer)) {
      processes::all(false);
      return out;
    }
    if (!processes::all(true)) {  // the first process could not open its results
      out.status = kExitIo;
      return out;
    }
    // Another process's writer: its part of the history's values and its pieces of the frames.
    if (!writes) try {
        writer = std::make_unique<ResultsWriter>(input, *first, input.output.directory, nullptr);
      } catch (const OutputError& e) {
        out.status = kExitIo;
        out.errors.push_back(e.what());
        return out;
      }
  }
  const int n = static_cast<int>(input.steps.size());
  if (!opt.quiet)
    say(stderr, "velum: {} nodes, {} elements, {} analysis steps; results in {}\n", all_nodes,
        input.model.num_elements(), n, out.directory.string());
  RunSummary& summary = out.summary;
  summary.elements = input.model.num_elements();
  // SIGINT, SIGTERM inside the loops that may run long: under mpirun every process asks at
  // the same points, and all stop together.
  for (AnalysisStep& s : input.steps)
    s.analysis.newton.interrupted = [several] {
      const bool mine = InterruptGuard::signal_received() != 0;
      return several ? !processes::all(!mine) : mine;
    };
  summary.warnings = input.warnings;  // the reader's (not printed under --quiet)
  StageObserver obs;
  obs.begin = [&](int k, MechanicalSystem& sys) {
    writer->begin_analysis_step(k + 1, sys);
    summary.dofs = std::max(summary.dofs, static_cast<int>(sys.global_size()));
    const AnalysisStep& s = input.steps[static_cast<size_t>(k)];
    if (!opt.quiet)
      say(stderr, "velum: step {}/{} '{}': {}, {} equations\n", k + 1, n, s.name,
          s.analysis.type_name(), sys.global_size());
  };
  std::exception_ptr output_failure;  // an OutputError, carried out of the analysis
  obs.step = [&](int, const StepSnapshot& snap) {
    bool written = true;
    try {
      write_step_output(*writer, snap, several);
    } catch (const OutputError&) {
      output_failure = std::current_exception();
      written = false;
    }
    summary.final_time = snap.step.t;
    const bool go = written && (!opt.on_step || opt.on_step(snap.step)) &&
                    InterruptGuard::signal_received() == 0;
    return several ? processes::all(go) : go;
  };
  obs.warn = [&](const std::string& w) {
    if (!opt.quiet) say(stderr, "warning: {}\n", w);
  };
  const StagedResult r = run_stages(input.steps, prepared, input.model, obs);
  if (!writes) {  // the first process reports the run
    if (!r.completed) out.status = kExitSolveFailed;
    return out;
  }
  if (output_failure) try {
      std::rethrow_exception(output_failure);
    } catch (const OutputError& e) {
      out.status = kExitIo;
      out.errors.push_back(e.what());
      summary.converged = false;  // summary.json says so (where it can), not "running"
      summary.reason = fmt::format("the results could not be written: {}", e.what());
      finish_summary(*writer, summary, opt.started, cpu_at_start, out);
      return out;
    }
  for (int k = 0; k < n; ++k) {
    const AnalysisStep& s = input.steps[static_cast<size_t>(k)];
    const StepOutcome& o = r.steps[static_cast<size_t>(k)];
    StepSummary& a = summary.analysis_steps.emplace_back();
    a.name = s.name;
    a.type = s.analysis.type_name();
    a.status = !o.run ? "not run" : k == r.failed ? "failed" : "converged";
    if (!o.run) continue;
    a.start_time = o.t_start, a.end_time = o.t_end;
    a.steps = o.result.loop.steps, a.newton_iterations = o.result.loop.iterations;
    a.integrator = o.result.integrator;
    a.external_work = o.result.energy.external_work;
    if (k == r.failed) a.reason = r.reason;
    if (s.analysis.type == AnalysisSettings::Type::kFormFinding) {
      a.form_updates = summary.form_updates = o.form.updates;
      a.form_residual = summary.form_residual = o.form.residual;
    }
    summary.steps += o.result.loop.steps;
    summary.newton_iterations += o.result.loop.iterations;
    summary.factorizations += static_cast<int>(o.result.loop.factorizations);
    summary.integrator = o.result.integrator;
    summary.solver = o.result.solver;
    for (const auto& w : o.result.warnings)
      summary.warnings.push_back(fmt::format("step '{}': {}", s.name, w));
  }
  summary.converged = r.completed;
  summary.reason = r.reason;
  summary.energy = r.energy;
  out.stopped = r.stopped;
  if (!r.completed) out.status = kExitSolveFailed;
  if (const int sig = InterruptGuard::signal_received(); sig && !r.completed) {
    mark_interrupted(sig, fmt::format("at t = {:.6g} ({})", summary.final_time, r.reason), summary,
                     out);
  }
  if (!finish_summary(*writer, summary, opt.started, cpu_at_start, out)) return out;
  if (out.status == kExitSolveFailed) {
    out.errors.push_back(fmt::format("the solve failed at t = {:.6g} (last output kept in {}): {}",
                                     summary.final_time, out.directory.string(), r.reason));
    return out;
  }
  if (out.status == kExitInterrupted || out.status == kExitTerminated) return out;
  if (!opt.quiet)
    say(stderr,
        "velum: converged ({} steps); energy: kinetic {:.6g}, strain {:.6g}, external work "
        "{:.6g}, damping {:.6g}\n",
        n, summary.energy.kinetic, summary.energy.strain, summary.energy.external_work,
        summary.energy.damping);
  return out;
}

std::string describe_steps(const ModelInput& in) {
  std::string s;
  double t = 0;
  for (size_t k = 0; k < in.steps.size(); ++k) {
    const AnalysisStep& st = in.steps[k];
    const double end = t + st.analysis.time.t_end;
    s += fmt::format(
        "step {}:{:<{}}'{}': {}, t = {:.6g} to {:.6g} (step {:.6g}); {} boundary, {} loads\n",
        k + 1, "", k + 1 < 10 ? 5 : 4, st.name, st.analysis.type_name(), t, end,
        st.analysis.time.step, k == 0 || st.boundary_given ? "its own" : "held",
        k == 0 || st.loads_given ? "its own" : "held");
    t = end;
  }
  return s;
}

}  // namespace velum::run
