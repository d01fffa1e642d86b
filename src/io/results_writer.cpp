#include "velum/io/results_writer.hpp"

#include "velum/io/json_text.hpp"
#include "velum/parallel/model_piece.hpp"
#include "velum/parallel/processes.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <system_error>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

namespace velum::io {
namespace {

/// Opens a results file for writing without following a symbolic link put in its place (which
/// could point out of the folder); null with errno set on failure.
std::FILE* open_output(const std::filesystem::path& path, bool append) {
  const int fd =
      ::open(path.c_str(),
             O_WRONLY | O_CREAT | O_CLOEXEC | O_NOFOLLOW | (append ? O_APPEND : O_TRUNC), 0666);
  if (fd < 0) return nullptr;
  std::FILE* f = ::fdopen(fd, append ? "ab" : "wb");
  if (!f) ::close(fd);
  return f;
}

/// Why a results file could not be opened (errno), in words.
std::string open_failure(const std::filesystem::path& path) {
  if (errno == ELOOP)
    return fmt::format(
        "cannot write {}: it is a symbolic link (results are not written through "
        "links; remove it)",
        path.string());
  return fmt::format("cannot write {}: {}", path.string(), std::strerror(errno));
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::FILE* f = open_output(tmp, false);
    if (!f) throw OutputError(open_failure(tmp));
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

}  // namespace

ResultsWriter::ResultsWriter(const ModelInput& input, MechanicalSystem& system,
                             std::filesystem::path directory, const WriterPosition* resume)
    : input_(input),
      system_(&system),
      records_(processes::rank() == 0),
      dir_(std::move(directory)),
      labels_(cell_labels(input.model, input.block_materials)) {
  if (input_.output.fields)
    frames_.emplace(input_, dir_, system.assembler(), processes::rank(), processes::count());
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
    history_ = open_output(h, true);
    if (!history_) throw OutputError(open_failure(h));
    steps_ = open_output(sp, true);
    if (!steps_) throw OutputError(open_failure(sp));
    std::fseek(history_, 0, SEEK_END);
    std::fseek(steps_, 0, SEEK_END);
    frame_times_ = resume->frame_times;
    if (input_.output.fields) write_legend();
    return;
  }
  if (input_.output.fields) write_legend();
  history_ = open_output(h, false);
  if (!history_) throw OutputError(open_failure(h));
  std::string header = input_.steps.empty() ? "time" : "time,analysis_step";
  for (const auto& e : input_.output.history) header += "," + e.name;
  std::fprintf(history_, "%s\n", header.c_str());
  if (std::fflush(history_) != 0) throw OutputError(fmt::format("cannot write {}", h.string()));
  steps_ = open_output(sp, false);
  if (!steps_) throw OutputError(open_failure(sp));
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
  // Positions, reactions and cells once per output time: for the history row, the frame and
  // the summary's extremes. Under mpirun each process computes the cells of its own elements
  // and its share of the reactions, completed at the nodes it shares with other processes;
  // the history's values are reduced to the first process, which writes them (every process
  // takes part: the collective calls all come before any file is written, so that an output
  // error on one process leaves none of them waiting).
  const Assembler& assembler = system_->assembler();
  const double t = snap.step.t;
  const NodePositions U = system_->displacements(t, snap.state.u);
  const NodePositions V = system_->velocities(snap.state.v);
  const NodePositions x = input_.model.X + U;
  NodePositions R;
  if (input_.output.fields || needs_reactions()) R = reactions(snap, x);
  // The accounts of loads that keep one (a gas chamber's first law), as of this output.
  accounts_.clear();
  contact_accounts_.clear();
  for (const auto& term : system_->loads())
    if (std::string a = term->account_json(); !a.empty()) {
      std::string& to = a.starts_with("{\"contact\"") ? contact_accounts_ : accounts_;
      to += (to.empty() ? "    " : ",\n    ") + a;
    }
  const std::vector<double> row = history_row(snap, U, V, x, R);
  const std::vector<std::vector<int>>& own = assembler.own_by_block();
  const FrameFields f = evaluate_cells(input_.model, x, own, !input_.output.fields);
  // The extremes: not of the initial state (often unloaded).
  if (snap.step.step > 0) update_extremes(t, U, f, own);
  std::vector<std::vector<double>> averaged;
  std::vector<double> gas;
  if (input_.output.fields) {
    averaged = frames_->average_to_nodes(f, assembler);
    gas = system_->load_cell_field("gas_pressure", t, x);  // collective
    node_fields_.clear();
    for (const char* name : {"contact_pressure", "contact_gap", "contact_status"})
      if (auto v = system_->load_node_field(name, t, x); !v.empty())
        node_fields_.emplace_back(name, std::move(v));
  }
  if (records_) write_history_row(snap, row);
  if (input_.output.fields) write_frame(t, U, V, R, f, averaged, gas);
}

bool ResultsWriter::needs_reactions() const {
  for (const auto& h : input_.output.history)
    if (h.quantity == HistoryEntry::Quantity::kReaction) return true;
  return false;
}

NodePositions ResultsWriter::reactions(const StepSnapshot& snap, const NodePositions& x) const {
  // This process's share of internal minus external force (its elements, the nodal loads of
  // the nodes it keeps), completed at the shared nodes: whole at every node of its piece. The
  // external forces as the supports carry them (an enclosed gas: its traction on the sheet).
  const Assembler& a = system_->assembler();
  NodePositions Fint, R;
  {
    const Assembler::LocalShare share(a);
    a.internal(x, Fint, nullptr);
    R = Fint - system_->external_forces(snap.step.t, snap.state.u, snap.state.v, true);
  }
  a.sum_at_shared_nodes(R);
  system_->dofs().keep_eliminated(R);
  return R;
}

void ResultsWriter::update_extremes(double t, const NodePositions& U, const FrameFields& f,
                                    const std::vector<std::vector<int>>& own) {
  const Model& model = input_.model;
  // The extremes over this process's cells (in the model's order, the first of equal values
  // kept), then over the processes on the first.
  Extreme stress, force_per_length, min_cable, max_cable;
  std::array<long, 4> cell{};
  auto offer = [&](Extreme& x, long& at, double v, long id, size_t k, bool larger) {
    const bool was = x.found;
    const double before = x.value;
    x.offer(v, id, t, larger);
    if (x.found && (!was || x.value != before)) at = static_cast<long>(k);  // replaced
  };
  size_t first = 0, value = 0;  // the block's first cell; f's entry (own cells only)
  for (size_t b = 0; b < model.blocks.size(); ++b) {
    const auto& ids = input_.element_ids[b];
    for (int e : own[b]) {
      const size_t k = first + static_cast<size_t>(e), i = value++;
      const long id = ids[static_cast<size_t>(e)];
      offer(stress, cell[0], f.cells[kTrueStressMax].values[i], id, k, true);
      offer(force_per_length, cell[1], f.cells[kForcePerLengthMax].values[i], id, k, true);
      offer(min_cable, cell[2], f.cells[kCableForce].values[i], id, k, false);
      offer(max_cable, cell[3], f.cells[kCableForce].values[i], id, k, true);
    }
    first += static_cast<size_t>(model.blocks[b]->size());
  }
  const Extreme* local[] = {&stress, &force_per_length, &min_cable, &max_cable};
  Extreme* running[] = {&max_stress_, &max_force_per_length_, &min_cable_force_, &max_cable_force_};
  const bool larger[] = {true, true, false, true};
  if (processes::count() == 1) {
    for (int i = 0; i < 4; ++i)
      if (local[i]->found) running[i]->offer(local[i]->value, local[i]->id, t, larger[i]);
  } else {
    std::vector<double> mine;  // per extreme: value (NaN: none), id, cell
    for (int i = 0; i < 4; ++i)
      mine.insert(mine.end(),
                  {local[i]->found ? local[i]->value : std::numeric_limits<double>::quiet_NaN(),
                   static_cast<double>(local[i]->id), static_cast<double>(cell[i])});
    // The largest displacement over the nodes this process keeps (the first of equal ones):
    // its value, its node's index in the whole model and its id.
    double most = -1, node = -1, id = 0;
    const ModelPiece& piece = *model.piece;
    for (int n = 0; n < model.num_nodes(); ++n)
      if (system_->assembler().keeps_node(n) && U.col(n).norm() > most)
        most = U.col(n).norm(), node = piece.global_node[static_cast<size_t>(n)],
        id = static_cast<double>(model.node_ids[static_cast<size_t>(n)]);
    mine.insert(mine.end(), {most, node, id});
    const std::vector<double> all = processes::gather(mine);
    if (!records_) return;
    most = -1, node = -1;  // over the processes: the first node of equal ones
    for (size_t p = 0; p < all.size() / mine.size(); ++p) {
      const double* v = all.data() + (p + 1) * mine.size() - 3;
      if (v[1] >= 0 && (v[0] > most || (v[0] == most && v[1] < node)))
        most = v[0], node = v[1], id = v[2];
    }
    if (node >= 0) max_displacement_.offer(most, static_cast<long>(id), t, true);
    for (int i = 0; i < 4; ++i) {
      // The best over the processes; of equal values the first cell in the model's order.
      double best = std::numeric_limits<double>::quiet_NaN(), id = 0, at = 0;
      for (size_t p = 0; p < all.size() / mine.size(); ++p) {
        const double* v = all.data() + p * mine.size() + 3 * i;
        if (std::isnan(v[0])) continue;
        if (std::isnan(best) || (larger[i] ? v[0] > best : v[0] < best) ||
            (v[0] == best && v[2] < at))
          best = v[0], id = v[1], at = v[2];
      }
      running[i]->offer(best, static_cast<long>(id), t, larger[i]);
    }
    return;
  }
  if (!records_) return;
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
                                    const NodePositions& x, const NodePositions& R) {
  using Q = HistoryEntry::Quantity;
  const Model& model = input_.model;
  const Assembler& a = system_->assembler();
  // Under mpirun this process's part of the value, summed over the processes by the caller:
  // a value of the replicated state from the first process alone, a point's stress from the
  // process computing its element, a reaction from the processes keeping its nodes.
  const bool first = processes::rank() == 0;
  switch (h.quantity) {
    // A node's state from the process keeping it (it holds the node's equations; every
    // process on one).
    case Q::kDisplacement:
      return a.keeps_node(h.node) ? U(h.component, h.node) : 0.0;
    case Q::kVelocity:
      return a.keeps_node(h.node) ? V(h.component, h.node) : 0.0;
    case Q::kPosition:
      return a.keeps_node(h.node) ? model.X(h.component, h.node) + U(h.component, h.node) : 0.0;
    case Q::kReaction: {
      double sum = 0;
      for (int n : h.nodes)
        if (a.keeps_node(n)) sum += R(h.component, n);
      return sum;
    }
    case Q::kFiberAngleChange: {
      if (!a.owns(h.block, h.element)) return 0.0;
      const double angle =
          model.blocks[h.block]->surface()->output_at(h.element, h.xi, x).fiber_angle_change;
      return h.degrees ? angle * kDeg : angle;
    }
    case Q::kStress: {
      if (!a.owns(h.block, h.element)) return 0.0;
      const MembraneStress s = model.blocks[h.block]->surface()->output_at(h.element, h.xi, x);
      switch (h.component) {
        case 0:
          return s.max;
        case 1:
          return s.min;
        default:
          return s.sheet[h.component - 2];
      }
    }
    case Q::kForce:
      return a.owns(h.block, h.element) ? model.blocks[h.block]->output(h.element, x).cable_force
                                        : 0.0;
    case Q::kSlip:
      return a.owns(h.block, h.element)
                 ? model.blocks[h.block]->sliding()->slip(h.element, h.chain_place, x)
                 : 0.0;
    case Q::kKineticEnergy:
      return first ? snap.energy.kinetic : 0.0;
    case Q::kStrainEnergy:
      return first ? snap.energy.strain : 0.0;
    case Q::kExternalWork:
      return first ? snap.energy.external_work : 0.0;
    case Q::kGasVolume: {
      const double volume = *system_->load_quantity_at("gas_volume", h.load, snap.step.t, x);
      return first ? volume : 0.0;
    }
    case Q::kGasPressure: {
      const double p = *system_->load_quantity_at("gas_pressure", h.load, snap.step.t, x);
      return first ? p : 0.0;
    }
    case Q::kGasTemperature:
    case Q::kGasMass:
    case Q::kGasMassFlow: {
      const std::string name = h.quantity == Q::kGasTemperature ? std::string("gas_temperature")
                               : h.quantity == Q::kGasMass      ? std::string("gas_mass")
                                                                : "gas_mass_flow:" + h.flow;
      const double q = system_->load_quantity_at(name, h.load, snap.step.t, x).value_or(0.0);
      return first ? q : 0.0;
    }
    case Q::kContactForce:
    case Q::kContactArea:
    case Q::kRigidPosition:
    case Q::kRigidVelocity:
    case Q::kRigidRotation:
    case Q::kRigidAngularVelocity: {
      // A contact force: the sum of this process's nodes over the contacts with the body
      // (summed over processes with the row); a body's motion: from its first contact.
      double sum = 0;
      for (const auto& term : system_->loads())
        if (auto q = term->quantity_at(h.flow, snap.step.t, x)) {
          if (h.quantity == Q::kRigidPosition || h.quantity == Q::kRigidVelocity ||
              h.quantity == Q::kRigidRotation || h.quantity == Q::kRigidAngularVelocity)
            return first ? *q : 0.0;
          sum += *q;
        }
      return sum;
    }
  }
  return 0;
}

void ResultsWriter::write_history(const StepSnapshot& snap) {
  NodePositions U, V, x, R;
  if (!input_.output.history.empty()) {
    U = system_->displacements(snap.step.t, snap.state.u);
    V = system_->velocities(snap.state.v);
    x = input_.model.X + U;
    if (needs_reactions()) R = reactions(snap, x);
  }
  // The accounts of loads that keep one (a gas chamber's first law), as of this output.
  accounts_.clear();
  contact_accounts_.clear();
  for (const auto& term : system_->loads())
    if (std::string a = term->account_json(); !a.empty()) {
      std::string& to = a.starts_with("{\"contact\"") ? contact_accounts_ : accounts_;
      to += (to.empty() ? "    " : ",\n    ") + a;
    }
  const std::vector<double> row = history_row(snap, U, V, x, R);
  if (records_) write_history_row(snap, row);
}

std::vector<double> ResultsWriter::history_row(const StepSnapshot& snap, const NodePositions& U,
                                               const NodePositions& V, const NodePositions& x,
                                               const NodePositions& R) {
  std::vector<double> row;
  row.reserve(input_.output.history.size());
  for (const auto& h : input_.output.history) row.push_back(history_value(h, snap, U, V, x, R));
  if (processes::count() > 1) processes::sum(row.data(), static_cast<long>(row.size()));
  return row;
}

void ResultsWriter::write_history_row(const StepSnapshot& snap, const std::vector<double>& values) {
  std::string row = fmt::format("{:.12g}", snap.step.t);
  if (!input_.steps.empty()) row += fmt::format(",{}", analysis_step_);
  for (double v : values) row += fmt::format(",{:.12g}", v);
  row += "\n";
  if (std::fputs(row.c_str(), history_) < 0 || std::fflush(history_) != 0)
    throw OutputError(fmt::format("cannot write {}", (dir_ / "history.csv").string()));
}

void ResultsWriter::write_frame(double t, const NodePositions& U, const NodePositions& V,
                                const NodePositions& R, const FrameFields& f,
                                const std::vector<std::vector<double>>& averaged,
                                const std::vector<double>& gas) {
  frames_->write(static_cast<int>(frame_times_.size()), {.t = t,
                                                         .U = U,
                                                         .V = V,
                                                         .R = R,
                                                         .f = f,
                                                         .averaged = averaged,
                                                         .gas = gas,
                                                         .node_fields = &node_fields_});
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
        "\"shared_nodes\": {}, \"neighbours\": {}, \"cpu_seconds\": {}, \"peak_memory_mb\": "
        "{}}},\n",
        r.process_elements.size(), r.partition, list(r.process_elements), r.shared_nodes,
        list(r.process_neighbours), list(r.process_cpu_seconds), list(r.process_memory_mb));
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
  if (const ExplicitStepReport& x = r.explicit_step; x.estimates > 0) {
    s += fmt::format(
        "  \"explicit_step\": {{\"safety\": {}, \"stable_step_start\": {}, \"stable_step_last\": "
        "{}, "
        "\"smallest_step\": {}, \"largest_step\": {}, \"estimates\": {}, "
        "\"estimate_evaluations\": {}",
        json_number(r.safety), json_number(x.first), json_number(x.last), json_number(x.smallest),
        json_number(x.largest), x.estimates, x.evaluations);
    if (r.target_step > 0)
      s += fmt::format(
          ", \"mass_scaling\": {{\"target_step\": {}, \"added_mass\": {}, \"model_mass\": {}, "
          "\"added_fraction\": {}, \"nodes\": {}}}",
          json_number(r.target_step), json_number(x.added_mass), json_number(x.model_mass),
          json_number(x.model_mass > 0 ? x.added_mass / x.model_mass : 0.0), x.scaled_nodes);
    s += "},\n";
  }
  std::string warnings;
  for (const auto& w : r.warnings) warnings += (warnings.empty() ? "" : ", ") + json_string(w);
  s += fmt::format("  \"warnings\": [{}],\n", warnings);
  if (!accounts_.empty()) s += "  \"gas\": [\n" + accounts_ + "\n  ],\n";
  if (!contact_accounts_.empty()) s += "  \"contact\": [\n" + contact_accounts_ + "\n  ],\n";
  s += fmt::format(
      "  \"energy\": {{\"kinetic\": {}, \"strain\": {}, \"external_work\": {}, \"damping\": {}}}\n",
      json_number(r.energy.kinetic), json_number(r.energy.strain),
      json_number(r.energy.external_work), json_number(r.energy.damping));
  s += "}\n";
  write_file_atomically(dir_ / "summary.json", s);
}

}  // namespace velum::io
