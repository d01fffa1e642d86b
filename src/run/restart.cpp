// Checkpoints of a run and `velum run --restart DIR`: what a checkpoint records besides the
// state (the model's fingerprint, the processes, where the results files stood) and the checks
// that it still fits the model and the folder before anything in DIR is touched.
#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "run_parts.hpp"
#include "velum/io/frame_writer.hpp"
#include "velum/parallel/processes.hpp"

namespace velum::run {
namespace {

/// The first line of a fingerprint that covers the loads, the boundary and the mesh (a
/// checkpoint of an older Velum has none: it is refused, as it cannot tell a changed load).
constexpr const char* kFingerprintVersion = "fingerprint 3";

/// What a restarted model must share with the one that wrote the checkpoint, one line each (so
/// that a mismatch names its line): the analysis, the history columns, the frames, the
/// materials and sections, the loads, the boundary and the mesh. time.end may change (a longer
/// one continues a finished run).
std::string fingerprint(const ModelInput& in) {
  const AnalysisSettings& a = in.analysis;
  std::string f =
      fmt::format("{}\nanalysis: {} ({})\n", kFingerprintVersion, a.type_name(), a.method());
  f += "history columns:";
  for (const auto& h : in.output.history) f += " " + h.name;
  f += fmt::format("\nframes: {}\n", in.output.fields ? "written" : "none");
  f += "materials and sections:\n" + in.materials_yaml + "\n";
  return f + in.restart_yaml;
}

/// The first line where two fingerprints differ, and the one line of each there.
std::pair<std::string, std::string> first_difference(const std::string& a, const std::string& b) {
  const auto header = [](const std::string& l) {
    return l.size() > 2 && l.front() == '[' && l.back() == ']';
  };
  std::istringstream sa(a), sb(b);
  std::string la, lb, section;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(sa, la));
    const bool gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return {"", ""};
    if (!ga) la = "(nothing)";
    if (!gb) lb = "(nothing)";
    if (la != lb) {
      // One section longer than the other: the shorter one's next header is not its content.
      if (header(la) && !header(lb)) la = "(nothing more)";
      if (header(lb) && !header(la)) lb = "(nothing more)";
      if (la.rfind("materials", 0) == 0 || section.empty()) return {la, lb};
      return {section + " " + la, section + " " + lb};
    }
    if (la == "materials and sections:") section = "materials and sections:";
    if (header(la)) section = la.substr(1, la.size() - 2) + ":";
  }
}

/// A results file as the checkpoint left it: a regular file at least `bytes` long whose rows
/// end there (a user's edit that cut it short would be padded with NUL bytes otherwise, and an
/// edited size would grow it without end).
void check_results_file(const std::filesystem::path& file, long bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::symlink_status(file, ec);
  if (!fs::is_regular_file(st))
    throw std::runtime_error(
        fmt::format("{}: {} (the checkpoint's run wrote it there): it cannot be continued",
                    file.string(), fs::exists(st) ? "not a regular file" : "missing"));
  const auto size = fs::file_size(file, ec);
  if (ec || size < static_cast<std::uintmax_t>(bytes))
    throw std::runtime_error(
        fmt::format("{}: {} bytes, but the checkpoint stood at byte {}: the file was cut short "
                    "since (run the model again from its start)",
                    file.string(), size, bytes));
  if (bytes == 0) return;
  std::ifstream f(file, std::ios::binary);
  f.seekg(bytes - 1);
  char last = 0;
  if (!f.get(last) || last != '\n')
    throw std::runtime_error(
        fmt::format("{}: byte {}, where the checkpoint stood, does not end a row: the file was "
                    "changed since (run the model again from its start)",
                    file.string(), bytes));
}

}  // namespace

void save_checkpoint(const ResultsWriter& writer, const ModelInput& input, int dofs,
                     Checkpoint run) {
  const WriterPosition at = writer.position();
  write_checkpoint(writer.directory() / "checkpoint.bin",
                   CheckpointFile{.dofs = dofs,
                                  .model = input.file.filename().string(),
                                  .processes = processes::count(),
                                  .fingerprint = fingerprint(input),
                                  .run = std::move(run),
                                  .history_bytes = at.history_bytes,
                                  .steps_bytes = at.steps_bytes,
                                  .frame_times = at.frame_times});
}

std::optional<CheckpointFile> load_checkpoint(const std::filesystem::path& dir,
                                              const ModelInput& in, const MechanicalSystem& sys,
                                              std::vector<std::string>& errors) {
  const auto file = dir / "checkpoint.bin";
  try {
    if (in.analysis.path.method != PathSettings::Method::kLoadControl)
      throw std::runtime_error("--restart: path following (analysis.path) has no checkpoints");
    CheckpointFile c = read_checkpoint(file);
    if (c.fingerprint.rfind(std::string(kFingerprintVersion) + "\n", 0) != 0)
      throw std::runtime_error(fmt::format(
          "{}: written by an older Velum, whose checkpoints do not record the loads, the "
          "boundary and the node coordinates, so a changed model could not be told: run the "
          "model again from its start",
          file.string()));
    if (const auto [was, is] = first_difference(c.fingerprint, fingerprint(in)); !was.empty())
      throw std::runtime_error(fmt::format(
          "{}: written by another model ({}): it had \"{}\", this one has \"{}\"; a restart "
          "continues the same model (only time.end may change)",
          file.string(), c.model, was, is));
    if (c.dofs != sys.global_size() || c.run.state.u.size() != sys.global_size())
      throw std::runtime_error(
          fmt::format("{}: written by a model with {} equations ({}), this "
                      "one has {}",
                      file.string(), c.dofs, c.model, sys.global_size()));
    if (c.processes != processes::count())
      throw std::runtime_error(fmt::format(
          "{}: written by a run on {} process{}, this one has {}: restart it on as many (its "
          "frames are in {} piece{})",
          file.string(), c.processes, c.processes == 1 ? "" : "es", processes::count(), c.processes,
          c.processes == 1 ? "" : "s"));
    check_results_file(dir / "history.csv", c.history_bytes);
    check_results_file(dir / "steps.csv", c.steps_bytes);
    if (in.output.fields)
      for (size_t i = 0; i < c.frame_times.size(); ++i) {
        const auto frame = dir / FrameWriter::file(static_cast<int>(i), c.processes);
        if (!std::filesystem::is_regular_file(frame))
          throw std::runtime_error(fmt::format(
              "{}: missing, but the checkpoint's run wrote it (run the model again from its "
              "start)",
              frame.string()));
      }
    return c;
  } catch (const std::exception& e) {
    errors.push_back(e.what());
    return std::nullopt;
  }
}

}  // namespace velum::run
