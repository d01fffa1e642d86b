#include "velum/io/results_writer.hpp"

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

int vtk_type(std::string_view t) {
  if (t == "tri3") return 5;
  if (t == "tri6") return 22;
  if (t == "quad4") return 9;
  if (t == "quad8") return 23;
  if (t == "quad9") return 28;
  if (t == "cable2") return 3;
  return 21;  // cable3: VTK_QUADRATIC_EDGE (ends, then middle: Gmsh order)
}

// Appended raw binary: each array is a UInt64 byte count followed by the values. The arrays
// are laid out last first: meshio (5.0) reads raw appended data by finding each array's tag
// by its offset while rewriting the offsets of those it has read, and with ascending offsets
// it can find a rewritten tag instead (a CorruptionError on frames with many arrays); in
// reverse order the tag it looks for always precedes the rewritten ones.
class Appended {
 public:
  template <class T>
  std::string add(const std::string& attrs, const std::vector<T>& v) {
    const std::string tag = fmt::format("<DataArray {} format=\"appended\" offset=\"{}{}\"/>\n",
                                        attrs, kMark, chunks_.size());
    const std::uint64_t bytes = v.size() * sizeof(T);
    std::string& c = chunks_.emplace_back();
    c.reserve(sizeof bytes + bytes);
    c.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    c.append(reinterpret_cast<const char*>(v.data()), bytes);
    return tag;
  }
  /// `xml` with its offsets filled in, then the appended data section and the end of the file.
  std::string finish(const std::string& xml) const {
    std::vector<size_t> offset(chunks_.size());
    size_t at = 0;
    for (size_t k = chunks_.size(); k-- > 0;) offset[k] = at, at += chunks_[k].size();
    std::string out;
    out.reserve(xml.size() + at + 64);
    size_t from = 0;
    for (size_t k = 0; k < chunks_.size(); ++k) {
      const std::string mark = fmt::format("{}{}\"", kMark, k);
      const size_t pos = xml.find(mark, from);
      out.append(xml, from, pos - from);
      out += fmt::format("{}\"", offset[k]);
      from = pos + mark.size();
    }
    out.append(xml, from);
    out += "<AppendedData encoding=\"raw\">\n_";
    for (size_t k = chunks_.size(); k-- > 0;) out += chunks_[k];
    out += "\n</AppendedData>\n</VTKFile>\n";
    return out;
  }

 private:
  static constexpr const char* kMark = "@";
  std::vector<std::string> chunks_;
};

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
      dir_(std::move(directory)),
      labels_(cell_labels(input.model, input.block_materials)),
      average_(input.model) {
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
  return {.history_bytes = std::ftell(history_),
          .steps_bytes = std::ftell(steps_),
          .frame_times = frame_times_};
}

ResultsWriter::~ResultsWriter() {
  if (history_) std::fclose(history_);
  if (steps_) std::fclose(steps_);
}

void ResultsWriter::write_step(const AcceptedStep& step) {
  if (step.step == 0) return;  // the initial state is not a step
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
  // the summary's extremes. Under mpirun only the first process writes: the forces come from
  // every element here, with no communication (the others are not taking part).
  const Assembler::WholeMesh whole(system_->assembler());
  const double t = snap.step.t;
  const NodePositions U = system_->displacements(t, snap.state.u);
  const NodePositions V = system_->velocities(snap.state.v);
  const NodePositions x = input_.model.X + U;
  NodePositions R;
  bool have_R = false;
  if (input_.output.fields) R = reactions(snap, x), have_R = true;
  write_history_row(snap, U, V, x, R, have_R);
  const FrameFields f = evaluate_cells(input_.model, x);
  if (snap.step.step > 0) update_extremes(t, U, f);  // not the initial state (often unloaded)
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
  const NodePositions x = model.X + U;
  const int nn = model.num_nodes();
  const int ne = model.num_elements();
  std::vector<std::int64_t> conn, offsets, element_id;
  std::vector<std::int32_t> set_index, material_index;
  std::vector<std::uint8_t> types;
  conn.reserve(static_cast<size_t>(ne) * 4);
  offsets.reserve(ne);
  types.reserve(ne);
  element_id.reserve(ne);
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = model.blocks[bi];
    const int n = b->size();
    const std::uint8_t vt = static_cast<std::uint8_t>(vtk_type(b->type_name()));
    for (int e = 0; e < n; ++e) {
      for (int node : b->nodes(e)) conn.push_back(node);
      offsets.push_back(static_cast<std::int64_t>(conn.size()));
      types.push_back(vt);
      element_id.push_back(input_.element_ids[bi][static_cast<size_t>(e)]);
    }
    set_index.insert(set_index.end(), static_cast<size_t>(n), labels_.set_of_block[bi]);
    material_index.insert(material_index.end(), static_cast<size_t>(n),
                          labels_.material_of_block[bi]);
  }

  // The absolute pressure of the gas each element encloses (0: none).
  std::vector<double> gas(ne, 0.0);
  if (!model.gases.empty()) {
    std::vector<int> first(model.blocks.size(), 0);
    for (size_t b = 1; b < model.blocks.size(); ++b)
      first[b] = first[b - 1] + model.blocks[b - 1]->size();
    for (size_t i = 0; i < model.gases.size(); ++i) {
      const double p = gas_pressure(static_cast<int>(i), t, x);
      for (const auto& part : model.gases[i].parts)
        for (int e : part.elements) gas[static_cast<size_t>(first[part.block] + e)] = p;
    }
  }

  auto flat = [nn](const NodePositions& M) {
    return std::vector<double>(M.data(), M.data() + 3 * static_cast<size_t>(nn));
  };
  Appended app;
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml +=
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  xml += "<UnstructuredGrid>\n";
  xml += fmt::format(
      "<FieldData>{}</FieldData>\n",
      app.add("type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\"", std::vector<double>{t}));
  xml += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", nn, ne);
  xml += "<PointData Vectors=\"displacement\">\n";
  xml += app.add("type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"", flat(U));
  xml += app.add("type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"", flat(V));
  xml += app.add("type=\"Float64\" Name=\"reaction\" NumberOfComponents=\"3\"", flat(R));
  xml += app.add("type=\"Int64\" Name=\"node_id\"",
                 std::vector<std::int64_t>(model.node_ids.begin(), model.node_ids.end()));
  for (const CellArray& a : f.cells)
    if (a.averaged)
      xml += app.add(fmt::format("type=\"Float64\" Name=\"{}\"", a.name),
                     average_.to_nodes(model, a.values));
  xml += "</PointData>\n<CellData>\n";
  for (const CellArray& a : f.cells)  // scalars without NumberOfComponents: (n,) in meshio
    xml += app.add(a.components == 1
                       ? fmt::format("type=\"Float64\" Name=\"{}\"", a.name)
                       : fmt::format("type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"",
                                     a.name, a.components),
                   a.values);
  if (!f.wrinkle_state.empty())
    xml += app.add("type=\"Int32\" Name=\"wrinkle_state\"", f.wrinkle_state);
  xml += app.add("type=\"Int32\" Name=\"element_set\"", set_index);
  xml += app.add("type=\"Int32\" Name=\"material\"", material_index);
  xml += app.add("type=\"Int64\" Name=\"element_id\"", element_id);
  if (!model.gases.empty()) xml += app.add("type=\"Float64\" Name=\"gas_pressure\"", gas);
  xml += "</CellData>\n<Points>\n";
  xml += app.add("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", flat(model.X));
  xml += "</Points>\n<Cells>\n";
  xml += app.add("type=\"Int64\" Name=\"connectivity\"", conn);
  xml += app.add("type=\"Int64\" Name=\"offsets\"", offsets);
  xml += app.add("type=\"UInt8\" Name=\"types\"", types);
  xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";

  const std::string name = fmt::format("frame_{:05d}.vtu", frame_times_.size());
  write_file_atomically(dir_ / "frames" / name, app.finish(xml));
  frame_times_.push_back(t);
  write_pvd();
}

void ResultsWriter::write_pvd() {
  std::string s =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<Collection>\n";
  for (size_t i = 0; i < frame_times_.size(); ++i)
    s += fmt::format(
        "  <DataSet timestep=\"{:.12g}\" group=\"\" part=\"0\" "
        "file=\"frames/frame_{:05d}.vtu\"/>\n",
        frame_times_[i], i);
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
        "  \"processes\": {{\"count\": {}, \"elements\": {}, \"cpu_seconds\": {}, "
        "\"peak_memory_mb\": {}}},\n",
        r.process_elements.size(), list(r.process_elements), list(r.process_cpu_seconds),
        list(r.process_memory_mb));
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
