// The velum command line: parses arguments and hands over to velum::run's commands.
#include <malloc.h>

#include <CLI/CLI.hpp>

#include "velum/config.hpp"
#include "velum/io/run_control.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/run/commands.hpp"
#include "velum/run/fit_command.hpp"
#include "velum/run/huge_page_heap.hpp"
#include "velum/run/partition_command.hpp"
#include "velum/run/pattern_command.hpp"
#include "velum/run/plot_command.hpp"
#include "velum/run/seams_command.hpp"
#include "velum/solve/blas_kernels.hpp"

namespace {

// MPI is finalised on every way out of main once it was started (mpirun waits for it).
struct ProcessesGuard {
  ~ProcessesGuard() { velum::processes::finish(); }
};

}  // namespace

int main(int argc, char** argv) {
  // First: it may re-execute the program with OPENBLAS_CORETYPE set (blas_kernels.hpp), and
  // with a huge-page heap asked of glibc (huge_page_heap.hpp): one restart carries both. The
  // `velum` launcher (launcher.cpp) has asked for the heap already: then only the kernels can.
  const bool huge_page_heap = velum::run::request_huge_page_heap();
  velum::choose_blas_kernels(argv);
  if (huge_page_heap) velum::run::start_again(argv);
  velum::stop_idle_blas_threads();  // run_model starts as many as the run's threads
  velum::io::prepare_standard_streams();
  // Under mpirun every process runs this same program on the same model (docs/parallel.md).
  if (!velum::processes::start(&argc, &argv)) return velum::run::kExitBadInput;
  ProcessesGuard processes;
  // The sparse factorisations allocate and free large blocks at every Newton iteration: keep
  // them in the heap instead of mapping fresh (page-faulting, zeroed) memory each time
  // (an M_MMAP_THRESHOLD above 32 MiB is refused by glibc, so mapping is switched off).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{
      "Velum: geometrically nonlinear dynamics of anisotropic membranes and cables.\n"
      "Units are the model's own (any consistent set) and never converted."};
  app.set_version_flag("--version", std::string("velum ") + VELUM_VERSION);
  app.require_subcommand(1);

  velum::run::RunOptions run;
  std::string output;
  auto* run_cmd = app.add_subcommand("run", "Solve a model file and write its results");
  run_cmd->add_option("MODEL", run.model, "model file (YAML)")->required();
  run_cmd->add_option("-o,--output", output, "output directory (overrides output.directory)");
  run_cmd->add_option("--threads", run.threads, "number of OpenMP threads")
      ->check(CLI::PositiveNumber);
  run_cmd->add_flag("--quiet,-q", run.quiet, "print errors only");
  std::string restart;
  run_cmd->add_option("--restart", restart,
                      "continue the run in DIR from its last checkpoint (output.checkpoint); "
                      "results go on in DIR");

  std::filesystem::path check_model;
  auto* check_cmd = app.add_subcommand("check", "Validate a model file and print its statistics");
  check_cmd->add_option("MODEL", check_model, "model file (YAML)")->required();

  // Everything after `plot` goes to the plotting script, which documents its own options.
  auto* plot_cmd = app.add_subcommand(
      "plot",
      "Draw PNGs of a results folder: the deformed shape coloured by a field, and history "
      "columns (velum plot --help for the options)");
  plot_cmd->prefix_command();
  plot_cmd->set_help_flag();
  // Everything after `fit` goes to the Python module velum.fit, which documents its options.
  auto* fit_cmd = app.add_subcommand(
      "fit",
      "Fit a linear orthotropic law and a stress map to biaxial tests (velum fit --help for "
      "the options)");
  fit_cmd->prefix_command();
  fit_cmd->set_help_flag();
  std::filesystem::path import_deck, import_output;
  auto* import_cmd = app.add_subcommand(
      "import", "Write an Abaqus/CalculiX input deck (.inp) as a Velum model file");
  import_cmd->add_option("DECK", import_deck, "input deck (.inp)")->required();
  import_cmd->add_option("-o,--output", import_output, "model file to write (YAML)")->required();

  std::filesystem::path pattern_input, pattern_output;
  auto* pattern_cmd = app.add_subcommand(
      "pattern", "Flatten the model's panels into cutting patterns (DXF, SVG, patterns.json)");
  pattern_cmd
      ->add_option("MODEL", pattern_input, "model file (YAML), or a form-finding results folder")
      ->required();
  pattern_cmd->add_option("-o,--output", pattern_output, "folder to write the patterns in")
      ->required();

  std::filesystem::path seams_input, seams_output;
  auto* seams_cmd = app.add_subcommand(
      "seams",
      "Cut the model's surface into panels along the seams of its patterns: block "
      "(geodesics between points, or node paths), and write the model with the panels");
  seams_cmd->add_option("MODEL", seams_input, "model file (YAML), or a form-finding results folder")
      ->required();
  seams_cmd->add_option("-o,--output", seams_output, "model file to write (YAML)")->required();

  std::filesystem::path partition_input, partition_output;
  int partition_parts = 0;
  auto* partition_cmd = app.add_subcommand(
      "partition",
      "Split a model for P MPI processes: one part per process, read with mesh.parts so that "
      "no process holds the whole mesh");
  partition_cmd->add_option("MODEL", partition_input, "model file (YAML)")->required();
  partition_cmd->add_option("-n,--parts", partition_parts, "number of processes (parts)")
      ->required();
  partition_cmd->add_option("-o,--output", partition_output, "folder to write the parts in")
      ->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : velum::run::kExitBadInput;
  }
  try {
    if (run_cmd->parsed()) {
      if (!output.empty()) run.output = output;
      if (!restart.empty()) run.restart = restart;
      return velum::run::run_command(run);
    }
    if (plot_cmd->parsed()) return velum::run::plot_command(plot_cmd->remaining());
    if (fit_cmd->parsed()) return velum::run::fit_command(fit_cmd->remaining());
    if (import_cmd->parsed()) return velum::run::import_command(import_deck, import_output);
    if (pattern_cmd->parsed()) return velum::run::pattern_command(pattern_input, pattern_output);
    if (seams_cmd->parsed()) return velum::run::seams_command(seams_input, seams_output);
    if (partition_cmd->parsed())
      return velum::run::partition_command(partition_input, partition_parts, partition_output);
    return velum::run::check_command(check_model);
  } catch (const std::bad_alloc&) {
    velum::io::say(stderr, "error: out of memory: the model is too large for this machine\n");
    return velum::run::kExitBadInput;
  }
}
