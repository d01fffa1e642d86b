// `velum run` on a model with steps (analysis/stages.hpp): one results folder for all steps,
// history.csv and steps.csv with an analysis_step column, one frame series, and summary.json
// with the totals at the top level and each step in analysis_steps.
#include <fmt/format.h>

#include <algorithm>

#include "run_parts.hpp"
#include "velum/io/run_control.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::run {

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
  if (processes::count() > 1) return refuse("steps: a model with steps runs on one process");
  std::optional<OutputLock> lock;
  std::unique_ptr<ResultsWriter> writer;
  {
    std::unique_ptr<MechanicalSystem> first;  // the writer's until the first step begins
    try {
      first = std::make_unique<MechanicalSystem>(input.model);
    } catch (const std::exception& e) {
      return refuse(e.what());
    }
    if (!open_results(input, *first, input.output.directory, std::nullopt, out, lock, writer))
      return out;
  }
  const int n = static_cast<int>(input.steps.size());
  if (!opt.quiet)
    say(stderr, "velum: {} nodes, {} elements, {} analysis steps; results in {}\n",
        input.model.num_nodes(), input.model.num_elements(), n, out.directory.string());
  RunSummary& summary = out.summary;
  summary.elements = input.model.num_elements();
  // SIGINT, SIGTERM inside the loops that may run long (one process: run_staged refuses more).
  for (AnalysisStep& s : input.steps)
    s.analysis.newton.interrupted = [] { return InterruptGuard::signal_received() != 0; };
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
    try {
      writer->write_step(snap.step);
      if (snap.step.output_time) writer->write(snap);
    } catch (const OutputError&) {
      output_failure = std::current_exception();
      return false;
    }
    summary.final_time = snap.step.t;
    return (!opt.on_step || opt.on_step(snap.step)) && InterruptGuard::signal_received() == 0;
  };
  obs.warn = [&](const std::string& w) {
    if (!opt.quiet) say(stderr, "warning: {}\n", w);
  };
  const StagedResult r = run_stages(input.steps, input.model, obs);
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
