#include "velum/io/results_writer.hpp"

#include "velum/solve/processes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <system_error>

#include <sys/resource.h>

namespace velum::io {

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f)
      throw OutputError(fmt::format("cannot write {}: {}", tmp.string(), std::strerror(errno)));
    const size_t n = std::fwrite(text.data(), 1, text.size(), f);
    const bool ok = n == text.size() && std::fflush(f) == 0;
    if (std::fclose(f) != 0 || !ok)
      throw OutputError(fmt::format("cannot write {}: {}", tmp.string(), std::strerror(errno)));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec)
    throw OutputError(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
}

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

std::string json_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.12g}", v) : "null";
}

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      o += '\\', o += c;
    else if (c == '\n')
      o += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20)
      o += fmt::format("\\u{:04x}", static_cast<int>(c));
    else
      o += c;
  }
  return o + "\"";
}

}  // namespace

ResultsWriter::ResultsWriter(const ModelInput& input, MechanicalSystem& system,
                             std::filesystem::path directory, const WriterPosition* resume)
    : input_(input),
      system_(&system),
      records_(processes::rank() == 0),
      dir_(std::move(directory)),
      labels_(cell_labels(input.model, input.block_materials)) {
  if (input_.output.fields) {
    std::vector<std::vector<int>> own;
    for (size_t b = 0; b < input_.model.blocks.size(); ++b)
      own.push_back(system.assembler().own(static_cast<int>(b)));
    frames_.emplace(input_, dir_, own, processes::rank(), processes::count());
  }
  if (!records_) {  // another process than the first: its pieces of the frames only
    if (resume) frame_times_ = resume->frame_times;
    return;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec || !std::filesystem::is_directory(dir_))
    throw OutputError(fmt::format("cannot create the output directory {}: {}", dir_.string(),
                                  ec ? ec.message() : "not a directory"));
  if (input_.output.fields) {
    std::filesystem::create_directories(dir_ / "frames", ec);
    if (ec)
      throw OutputError(
          fmt::format("cannot create {}: {}", (dir_ / "frames").string(), ec.message()));
  }
  const auto h = dir_ / "history.csv";
  const auto sp = dir_ / "steps.csv";
  if (resume) {
    // Cut back what a run after the checkpoint may have written, then append.
    std::error_code ec1, ec2;
    std::filesystem::resize_file(h, static_cast<std::uintmax_t>(resume->history_bytes), ec1);
    std::filesystem::resize_file(sp, static_cast<std::uintmax_t>(resume->steps_bytes), ec2);
    if (ec1 || ec2)
      throw OutputError(fmt::format("cannot resume the results in {}: {}", dir_.string(),
                                    (ec1 ? ec1 : ec2).message()));
    history_ = std::fopen(h.c_str(), "ab");
    steps_ = std::fopen(sp.c_str(), "ab");
    if (!history_ || !steps_)
      throw OutputError(
          fmt::format("cannot append to {}: {}", dir_.string(), std::strerror(errno)));
    std::fseek(history_, 0, SEEK_END);
    std::fseek(steps_, 0, SEEK_END);
    frame_times_ = resume->frame_times;
    if (input_.output.fields) write_legend();
    return;
  }
  if (input_.output.fields) write_legend();
  history_ = std::fopen(h.c_str(), "w");
  if (!history_)
    throw OutputError(fmt::format("cannot write {}: {}", h.string(), std::strerror(errno)));
  std::string header = input_.steps.empty() ? "time" : "time,analysis_step";
  for (const auto& e : input_.output.history) header += "," + e.name;
  std::fprintf(history_, "%s\n", header.c_str());
  if (std::fflush(history_) != 0) throw OutputError(fmt::format("cannot write {}", h.string()));
  steps_ = std::fopen(sp.c_str(), "w");
  if (!steps_)
    throw OutputError(fmt::format("cannot write {}: {}", sp.string(), std::strerror(errno)));
  if (std::fputs(input_.steps.empty()
                     ? "step,time,step_size,iterations,factorizations,negative_pivots,residuals\n"
                     : "analysis_step,step,time,step_size,iterations,factorizations,"
                       "negative_pivots,residuals\n",
                 steps_) < 0 ||
      std::fflush(steps_) != 0)
    throw OutputError(fmt::format("cannot write {}", sp.string()));
}

WriterPosition ResultsWriter::position() const {
  return {.history_bytes = history_ ? std::ftell(history_) : 0,
          .steps_bytes = steps_ ? std::ftell(steps_) : 0,
          .frame_times = frame_times_};
}

ResultsWriter::~ResultsWriter() {
  if (history_) std::fclose(history_);
  if (steps_) std::fclose(steps_);
}

void ResultsWriter::write_step(const AcceptedStep& step) {
  if (step.step == 0 || !records_) return;  // the initial state is not a step
  const std::vector<double>* r = step.report ? &step.report->residuals : nullptr;
  std::string all;
  if (r)
    for (double x : *r) all += fmt::format("{}{:.3e}", all.empty() ? "" : " ", x);
  // Negative pivots: empty where unknown (dynamic steps, LU factorisations).
  const int neg = step.report ? step.report->negative_pivots : -1;
  const std::string row =
      (input_.steps.empty() ? std::string() : fmt::format("{},", analysis_step_)) +
      fmt::format("{},{:.12g},{:.6g},{},{},{},{}\n", step.step, step.t, step.h, step.iterations,
                  step.factorizations, neg >= 0 ? std::to_string(neg) : std::string(), all);
  if (std::fputs(row.c_str(), steps_) < 0 || std::fflush(steps_) != 0)
    throw OutputError(fmt::format("cannot write {}", (dir_ / "steps.csv").string()));
}

void ResultsWriter::write(const StepSnapshot& snap) {
  if (!records_ && !input_.output.fields) return;
  // Positions, reactions and cells once per output time: for the history row, the frame and
  // the summary's extremes. Under mpirun every process computes them here from every element,
  // with no communication (the first alone writes the history; each process its piece of
  // the frame, whose averaged fields need the cells around its boundary nodes).
  const Assembler::WholeMesh whole(system_->assembler());
  const double t = snap.step.t;
  const NodePositions U = system_->displacements(t, snap.state.u);
  const NodePositions V = system_->velocities(snap.state.v);
  const NodePositions x = input_.model.X + U;
  NodePositions R;
  bool have_R = false;
  if (input_.output.fields) R = reactions(snap, x), have_R = true;
  if (records_) write_history_row(snap, U, V, x, R, have_R);
  const FrameFields f = evaluate_cells(input_.model, x);
  // The extremes: not of the initial state (often unloaded).
  if (records_ && snap.step.step > 0) update_extremes(t, U, f);
  if (input_.output.fields) write_frame(t, U, V, R, f);
}

NodePositions ResultsWriter::reactions(const StepSnapshot& snap, const NodePositions& x) const {
  NodePositions Fint;
  system_->assembler().internal(x, Fint, nullptr);
  NodePositions R = Fint - system_->external_forces(snap.step.t, snap.state.u, snap.state.v);
  const DofMap& d = system_->dofs();
  for (int n = 0; n < input_.model.num_nodes(); ++n) {
    Vec3 local = d.to_local(n, R.col(n));
    for (int c = 0; c < 3; ++c)
      if (d.equation(n, c) >= 0) local[c] = 0;
    R.col(n) = d.to_global(n, local);
  }
  return R;
}

void ResultsWriter::update_extremes(double t, const NodePositions& U, const FrameFields& f) {
  const Model& model = input_.model;
  size_t k = 0;
  for (size_t b = 0; b < model.blocks.size(); ++b) {
    const auto& ids = input_.element_ids[b];
    for (int e = 0; e < model.blocks[b]->size(); ++e, ++k) {
      const long id = ids[static_cast<size_t>(e)];
      max_stress_.offer(f.cells[kTrueStressMax].values[k], id, t, true);
      max_force_per_length_.offer(f.cells[kForcePerLengthMax].values[k], id, t, true);
      min_cable_force_.offer(f.cells[kCableForce].values[k], id, t, false);
      max_cable_force_.offer(f.cells[kCableForce].values[k], id, t, true);
    }
  }
  for (int n = 0; n < model.num_nodes(); ++n)
    max_displacement_.offer(U.col(n).norm(), model.node_ids[static_cast<size_t>(n)], t, true);
}

void ResultsWriter::write_legend() const {
  auto list = [](const std::vector<std::string>& names) {
    std::string s;
    for (size_t i = 0; i < names.size(); ++i)
      s += fmt::format("{}{}", i ? ", " : "", json_string(names[i]));
    return "[" + s + "]";
  };
  write_file_atomically(dir_ / "legend.json",
                        fmt::format("{{\n  \"element_set\": {},\n  \"material\": {}\n}}\n",
                                    list(labels_.sets), list(labels_.materials)));
}

double ResultsWriter::history_value(const HistoryEntry& h, const StepSnapshot& snap,
                                    const NodePositions& U, const NodePositions& V,
                                    const NodePositions& x, NodePositions& R, bool& have_R) {
  using Q = HistoryEntry::Quantity;
  const Model& model = input_.model;
  switch (h.quantity) {
    case Q::kDisplacement:
      return U(h.component, h.node);
    case Q::kVelocity:
      return V(h.component, h.node);
    case Q::kPosition:
      return model.X(h.component, h.node) + U(h.component, h.node);
    case Q::kReaction: {
      if (!have_R) {
        R = reactions(snap, x);
        have_R = true;
      }
      double sum = 0;
      for (int n : h.nodes) sum += R(h.component, n);
      return sum;
    }
    case Q::kFiberAngleChange: {
      const double a = model.blocks[h.block]->output_at(h.element, h.xi, x).fiber_angle_change;
      return h.degrees ? a * kDeg : a;
    }
    case Q::kStress: {
      const MembraneStress s = model.blocks[h.block]->output_at(h.element, h.xi, x);
      switch (h.component) {
        case 0:
          return s.max;
        case 1:
          return s.min;
        default:
          return s.sheet[h.component - 2];
      }
    }
    case Q::kKineticEnergy:
      return snap.energy.kinetic;
    case Q::kStrainEnergy:
      return snap.energy.strain;
    case Q::kExternalWork:
      return snap.energy.external_work;
    case Q::kGasVolume:
      return system_->assembler().gas_volume(h.load, x);
    case Q::kGasPressure:
      return gas_pressure(h.load, snap.step.t, x);
  }
  return 0;
}

double ResultsWriter::gas_pressure(int i, double t, const NodePositions& x) const {
  const GasLoad& gas = input_.model.gases[i];
  return gas.pressure(system_->assembler().gas_volume(i, x),
                      input_.model.function_value(gas.amount, t));
}

void ResultsWriter::write_history(const StepSnapshot& snap) {
  if (!records_) return;
  const Assembler::WholeMesh whole(system_->assembler());  // see write()
  NodePositions U, V, x, R;
  if (!input_.output.history.empty()) {
    U = system_->displacements(snap.step.t, snap.state.u);
    V = system_->velocities(snap.state.v);
    x = input_.model.X + U;
  }
  bool have_R = false;
  write_history_row(snap, U, V, x, R, have_R);
}

void ResultsWriter::write_history_row(const StepSnapshot& snap, const NodePositions& U,
                                      const NodePositions& V, const NodePositions& x,
                                      NodePositions& R, bool& have_R) {
  std::string row = fmt::format("{:.12g}", snap.step.t);
  if (!input_.steps.empty()) row += fmt::format(",{}", analysis_step_);
  for (const auto& h : input_.output.history)
    row += fmt::format(",{:.12g}", history_value(h, snap, U, V, x, R, have_R));
  row += "\n";
  if (std::fputs(row.c_str(), history_) < 0 || std::fflush(history_) != 0)
    throw OutputError(fmt::format("cannot write {}", (dir_ / "history.csv").string()));
}

void ResultsWriter::write_frame(double t, const NodePositions& U, const NodePositions& V,
                                const NodePositions& R, const FrameFields& f) {
  const Model& model = input_.model;
  // The absolute pressure of the gas each element encloses (0: none).
  std::vector<double> gas;
  if (!model.gases.empty()) {
    gas.assign(static_cast<size_t>(model.num_elements()), 0.0);
    const NodePositions x = model.X + U;
    std::vector<int> first(model.blocks.size(), 0);
    for (size_t b = 1; b < model.blocks.size(); ++b)
      first[b] = first[b - 1] + model.blocks[b - 1]->size();
    for (size_t i = 0; i < model.gases.size(); ++i) {
      const double p = gas_pressure(static_cast<int>(i), t, x);
      for (const auto& part : model.gases[i].parts)
        for (int e : part.elements) gas[static_cast<size_t>(first[part.block] + e)] = p;
    }
  }
  frames_->write(static_cast<int>(frame_times_.size()),
                 {.t = t, .U = U, .V = V, .R = R, .f = f, .gas = gas});
  frame_times_.push_back(t);
  if (records_) write_pvd();
}

void ResultsWriter::write_pvd() {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<Collection>\n";
  for (size_t i = 0; i < frame_times_.size(); ++i)
    s += fmt::format("  <DataSet timestep=\"{1:.12g}\" group=\"\" part=\"0\" file=\"{0}\"/>\n",
                     frames_->file(static_cast<int>(i)), frame_times_[i]);
  s += "</Collection>\n</VTKFile>\n";
  write_file_atomically(dir_ / "results.pvd", s);
}

void ResultsWriter::write_summary(const RunSummary& r) {
  std::string s = "{\n";
  s += fmt::format("  \"status\": \"{}\",\n", !r.status.empty() ? r.status
                                              : r.converged     ? "converged"
                                                                : "failed");
  if (!r.converged) s += fmt::format("  \"reason\": {},\n", json_string(r.reason));
  s += fmt::format("  \"steps\": {},\n  \"newton_iterations\": {},\n  \"factorizations\": {},\n",
                   r.steps, r.newton_iterations, r.factorizations);
  s += fmt::format("  \"wall_seconds\": {},\n  \"final_time\": {},\n", json_number(r.wall_seconds),
                   json_number(r.final_time));
  s += fmt::format("  \"dofs\": {},\n  \"elements\": {},\n", r.dofs, r.elements);
  s += fmt::format("  \"integrator\": {},\n  \"linear_solver\": {},\n", json_string(r.integrator),
                   json_string(r.solver));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);  // ru_maxrss: kibibytes on Linux
  s += fmt::format("  \"cpu_seconds\": {},\n  \"peak_memory_mb\": {},\n  \"threads\": {},\n",
                   json_number(r.cpu_seconds), json_number(usage.ru_maxrss / 1024.0), r.threads);
  if (r.process_elements.size() > 1) {
    auto list = [](const std::vector<double>& v) {
      std::string t;
      for (double x : v) t += (t.empty() ? "" : ", ") + json_number(x);
      return "[" + t + "]";
    };
    s += fmt::format(
        "  \"processes\": {{\"count\": {}, \"partition\": \"{}\", \"elements\": {}, "
        "\"shared_nodes\": {}, \"cpu_seconds\": {}, \"peak_memory_mb\": {}}},\n",
        r.process_elements.size(), r.partition, list(r.process_elements), r.shared_nodes,
        list(r.process_cpu_seconds), list(r.process_memory_mb));
  }
  auto extreme = [](const char* key, const Extreme& x, const char* where) {
    if (!x.found) return fmt::format("    \"{}\": null", key);
    return fmt::format("    \"{}\": {{\"value\": {}, \"{}\": {}, \"time\": {}}}", key,
                       json_number(x.value), where, x.id, json_number(x.time));
  };
  s += "  \"extremes\": {\n" + extreme("max_principal_stress", max_stress_, "element") + ",\n" +
       extreme("max_force_per_length", max_force_per_length_, "element") + ",\n" +
       extreme("max_displacement", max_displacement_, "node") + ",\n" +
       extreme("min_cable_force", min_cable_force_, "element") + ",\n" +
       extreme("max_cable_force", max_cable_force_, "element") + "\n  },\n";
  s += fmt::format("  \"frames\": {},\n", frame_times_.size());
  if (r.form_updates >= 0)
    s += fmt::format("  \"form_finding\": {{\"updates\": {}, \"residual\": {}}},\n", r.form_updates,
                     json_number(r.form_residual));
  if (!r.analysis_steps.empty()) {
    s += "  \"analysis_steps\": [\n";
    for (size_t i = 0; i < r.analysis_steps.size(); ++i) {
      const StepSummary& a = r.analysis_steps[i];
      s += fmt::format(
          "    {{\"name\": {}, \"type\": \"{}\", \"status\": \"{}\", \"start_time\": {}, "
          "\"end_time\": {}, \"steps\": {}, \"newton_iterations\": {}, \"integrator\": {}",
          json_string(a.name), a.type, a.status, json_number(a.start_time), json_number(a.end_time),
          a.steps, a.newton_iterations, json_string(a.integrator));
      if (!a.reason.empty()) s += fmt::format(", \"reason\": {}", json_string(a.reason));
      if (a.form_updates >= 0)
        s += fmt::format(", \"form_finding\": {{\"updates\": {}, \"residual\": {}}}",
                         a.form_updates, json_number(a.form_residual));
      s += fmt::format(", \"external_work\": {}}}{}\n", json_number(a.external_work),
                       i + 1 < r.analysis_steps.size() ? "," : "");
    }
    s += "  ],\n";
  }
  std::string warnings;
  for (const auto& w : r.warnings) warnings += (warnings.empty() ? "" : ", ") + json_string(w);
  s += fmt::format("  \"warnings\": [{}],\n", warnings);
  s += fmt::format(
      "  \"energy\": {{\"kinetic\": {}, \"strain\": {}, \"external_work\": {}, \"damping\": {}}}\n",
      json_number(r.energy.kinetic), json_number(r.energy.strain),
      json_number(r.energy.external_work), json_number(r.energy.damping));
  s += "}\n";
  write_file_atomically(dir_ / "summary.json", s);
}

}  // namespace velum::io
