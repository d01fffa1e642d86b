// `velum run` and `velum check`: the model read (its errors printed), then run_model or the
// model's statistics.
#include "velum/run/commands.hpp"

#include <fmt/format.h>

#include <map>

#include "run_parts.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/config.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::run {
namespace {

constexpr const char* kUnitsNote =
    "units: the model's own (any consistent set); nothing is converted";

/// Reads the model; on bad input prints every message and returns nullopt. Quiet: errors only
/// (the warnings are in summary.json).
std::optional<ModelInput> load(const std::filesystem::path& file, bool quiet = false) {
  try {
    ModelInput in = read_model(file);
    if (!quiet)
      for (const auto& w : in.warnings) say(stderr, "warning: {}\n", w);
    return in;
  } catch (const InputError& e) {
    for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
    say(stderr, "velum: {} error{} in {}\n", e.messages().size(),
        e.messages().size() == 1 ? "" : "s", file.string());
    return std::nullopt;
  }
}

/// Under mpirun, a model read in parts (mesh.parts): false, each named on the first process,
/// when a node id the model file names is held by no part (each process knows its own part
/// only). A collective call; true at once for a model read whole.
bool named_ids_found(const ModelInput& in) {
  if (processes::count() <= 1 || !in.model.piece) return true;
  const long n = processes::min(static_cast<long>(in.part_ids.size()));  // (the same everywhere)
  std::vector<double> here(static_cast<size_t>(n));
  for (size_t i = 0; i < here.size(); ++i) here[i] = in.part_ids[i].here ? 1 : 0;
  processes::sum(here.data(), n);
  bool found = true;
  for (size_t i = 0; i < here.size(); ++i)
    if (here[i] == 0) {
      found = false;
      if (processes::rank() == 0) say(stderr, "error: {}\n", in.part_ids[i].missing);
    }
  return found;
}

std::map<std::string, int> elements_per_type(const Model& m) {
  std::map<std::string, int> out;
  for (const auto& b : m.blocks) out[std::string(b->type_name())] += b->size();
  return out;
}

}  // namespace

int check_command(const std::filesystem::path& file) {
  // Once: the first process, and not again after a relaunch into velum-mpi (a PETSc model).
  if (processes::rank() == 0 && !processes::relaunched())
    say(stdout, "velum {} check: {}\n{}\n", VELUM_VERSION, file.string(), kUnitsNote);
  auto in = load(file);
  // Under mpirun (a model read in parts): every process goes on only if every one read it.
  if (processes::count() > 1 && !processes::all(in.has_value())) return kExitBadInput;
  if (!in) return kExitBadInput;
  if (!named_ids_found(*in)) return kExitBadInput;
  const Model& m = in->model;
  int dofs = 0;
  try {
    dofs = DofMap(m).num_equations();
  } catch (const std::exception& e) {
    say(stderr, "error: {}: {}\n", file.string(), e.what());
    return kExitBadInput;
  }
  // A model read in parts (mesh.parts): the model's totals and a line per part, printed by
  // the first process (the others' lines would interleave).
  const bool in_parts = m.piece != nullptr;
  std::vector<double> parts;  // per process: its nodes, own elements, equations
  if (in_parts) {
    long own = 0;
    for (const auto& o : m.piece->own) own += static_cast<long>(o.size());
    parts.assign(3 * static_cast<size_t>(processes::count()), 0.0);
    const size_t at = 3 * static_cast<size_t>(processes::rank());
    parts[at] = m.num_nodes(), parts[at + 1] = static_cast<double>(own), parts[at + 2] = dofs;
    processes::sum(parts.data(), static_cast<long>(parts.size()));
    if (processes::rank() != 0) return kExitOk;
  }
  auto total = [&](size_t column) {
    long n = 0;
    for (size_t k = column; k < parts.size(); k += 3) n += static_cast<long>(parts[k]);
    return n;
  };
  const long nodes = in_parts ? m.piece->global_nodes : m.num_nodes();
  const long equations = in_parts ? m.piece->global_equations : dofs;
  if (!in->title.empty()) say(stdout, "title:      {}\n", in->title);
  say(stdout, "nodes:      {}\n", nodes);
  if (in_parts) {
    say(stdout, "elements:   {}\n", total(1));
  } else {
    std::string per_type;
    for (const auto& [t, n] : elements_per_type(m)) per_type += fmt::format(" {} {}", t, n);
    say(stdout, "elements:   {} ({})\n", m.num_elements(),
        per_type.empty() ? "" : per_type.substr(1));
  }
  say(stdout, "blocks:     {}\n", m.blocks.size());
  for (size_t k = 0; k < parts.size(); k += 3)
    say(stdout, "part {}:     {} nodes (with the shared ones), {} own elements, {} equations\n",
        k / 3, static_cast<long>(parts[k]), static_cast<long>(parts[k + 1]),
        static_cast<long>(parts[k + 2]));
  say(stdout, "dofs:       {} equations ({} fixed or prescribed components)\n", equations,
      3 * nodes - equations);
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
      a.method(), a.time.t_end, a.time.step, a.time.min_step, a.time.adaptive ? ", adaptive" : "");
  say(stdout, "{}", describe_steps(*in));
  say(stdout, "output:     {} every {:.6g}, {} history column{}{}\n", in->output.directory.string(),
      in->output.interval, in->output.history.size(), in->output.history.size() == 1 ? "" : "s",
      in->output.fields ? ", fields" : "");
  say(stdout, "velum: {} is valid\n", file.string());
  return kExitOk;
}

int run_command(const RunOptions& opt) {
  RunControls controls;
  const bool speaks = processes::rank() == 0;  // under mpirun, the first process only
  if (!opt.quiet && speaks && !processes::relaunched())
    say(stderr, "velum {} run: {}\n{}\n", VELUM_VERSION, opt.model.string(), kUnitsNote);
  controls.output = opt.output;
  controls.threads = opt.threads;
  controls.quiet = opt.quiet;
  controls.restart = opt.restart;
  InterruptGuard interrupts;  // SIGINT, SIGTERM: finish the current step, then stop
  auto in = load(opt.model, opt.quiet);
  // Under mpirun every process goes on only if every process read the model (a part read,
  // mesh.parts, can fail on one process alone).
  if (processes::count() > 1 && !processes::all(in.has_value())) return kExitBadInput;
  if (!in) return kExitBadInput;
  if (!named_ids_found(*in)) return kExitBadInput;
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

}  // namespace velum::run
