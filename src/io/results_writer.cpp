#include "velum/io/results_writer.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <system_error>

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

// Appended raw binary: each array is a UInt64 byte count followed by the values.
class Appended {
 public:
  template <class T>
  std::string add(const std::string& attrs, const std::vector<T>& v) {
    const std::string tag =
        fmt::format("<DataArray {} format=\"appended\" offset=\"{}\"/>\n", attrs, data_.size());
    const std::uint64_t bytes = v.size() * sizeof(T);
    data_.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    data_.append(reinterpret_cast<const char*>(v.data()), bytes);
    return tag;
  }
  const std::string& data() const { return data_; }

 private:
  std::string data_;
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
    : input_(input), system_(system), dir_(std::move(directory)) {
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
    return;
  }
  history_ = std::fopen(h.c_str(), "w");
  if (!history_)
    throw OutputError(fmt::format("cannot write {}: {}", h.string(), std::strerror(errno)));
  std::string header = "time";
  for (const auto& e : input_.output.history) header += "," + e.name;
  std::fprintf(history_, "%s\n", header.c_str());
  if (std::fflush(history_) != 0) throw OutputError(fmt::format("cannot write {}", h.string()));
  steps_ = std::fopen(sp.c_str(), "w");
  if (!steps_)
    throw OutputError(fmt::format("cannot write {}: {}", sp.string(), std::strerror(errno)));
  if (std::fputs("step,time,step_size,iterations,factorizations,negative_pivots,residuals\n",
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
      fmt::format("{},{:.12g},{:.6g},{},{},{},{}\n", step.step, step.t, step.h, step.iterations,
                  step.factorizations, neg >= 0 ? std::to_string(neg) : std::string(), all);
  if (std::fputs(row.c_str(), steps_) < 0 || std::fflush(steps_) != 0)
    throw OutputError(fmt::format("cannot write {}", (dir_ / "steps.csv").string()));
}

void ResultsWriter::write(const StepSnapshot& snap) {
  write_history(snap);
  if (input_.output.fields) write_frame(snap);
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
        NodePositions Fint;
        system_.assembler().internal(x, Fint, nullptr);
        R = Fint - system_.external_forces(snap.step.t, snap.state.u, snap.state.v);
        const DofMap& d = system_.dofs();
        for (int n = 0; n < model.num_nodes(); ++n) {
          Vec3 local = d.to_local(n, R.col(n));
          for (int c = 0; c < 3; ++c)
            if (d.equation(n, c) >= 0) local[c] = 0;
          R.col(n) = d.to_global(n, local);
        }
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
      return system_.assembler().gas_volume(h.load, x);
    case Q::kGasPressure:
      return gas_pressure(h.load, snap.step.t, x);
  }
  return 0;
}

double ResultsWriter::gas_pressure(int i, double t, const NodePositions& x) const {
  const GasLoad& gas = input_.model.gases[i];
  return gas.pressure(system_.assembler().gas_volume(i, x),
                      input_.model.function_value(gas.amount, t));
}

void ResultsWriter::write_history(const StepSnapshot& snap) {
  const double t = snap.step.t;
  NodePositions U, V, x, R;
  if (!input_.output.history.empty()) {
    U = system_.displacements(t, snap.state.u);
    V = system_.velocities(snap.state.v);
    x = input_.model.X + U;
  }
  bool have_R = false;
  std::string row = fmt::format("{:.12g}", t);
  for (const auto& h : input_.output.history)
    row += fmt::format(",{:.12g}", history_value(h, snap, U, V, x, R, have_R));
  row += "\n";
  if (std::fputs(row.c_str(), history_) < 0 || std::fflush(history_) != 0)
    throw OutputError(fmt::format("cannot write {}", (dir_ / "history.csv").string()));
}

void ResultsWriter::write_frame(const StepSnapshot& snap) {
  const Model& model = input_.model;
  const double t = snap.step.t;
  const NodePositions U = system_.displacements(t, snap.state.u);
  const NodePositions V = system_.velocities(snap.state.v);
  const NodePositions x = model.X + U;
  const int nn = model.num_nodes();
  const int ne = model.num_elements();

  std::vector<double> smax(ne), smin(ne), dmax(3 * ne), dmin(3 * ne), angle(ne), force(ne),
      sheet(3 * ne);
  // Tension-field state, written when a section wrinkles (docs/wrinkling.md).
  const bool wrinkling = std::any_of(model.blocks.begin(), model.blocks.end(),
                                     [](const auto& b) { return b->tension_field(); });
  std::vector<std::int32_t> wstate(wrinkling ? ne : 0);
  std::vector<double> wdir(wrinkling ? 3 * ne : 0);
  std::vector<std::int64_t> conn, offsets;
  std::vector<std::uint8_t> types;
  conn.reserve(static_cast<size_t>(ne) * 4);
  offsets.reserve(ne);
  types.reserve(ne);
  int base = 0;
  for (const auto& b : model.blocks) {
    const int n = b->size();
    const bool membrane = b->kind() == ElementKind::kMembrane;
    const ElementBlock& blk = *b;
#pragma omp parallel for schedule(static)
    for (int e = 0; e < n; ++e) {
      const ElementOutput o = blk.output(e, x);
      const size_t k = static_cast<size_t>(base + e);
      if (membrane) {
        smax[k] = o.stress.max;
        smin[k] = o.stress.min;
        for (int c = 0; c < 3; ++c) {
          dmax[3 * k + c] = o.stress.dir_max[c];
          dmin[3 * k + c] = o.stress.dir_min[c];
        }
        angle[k] = o.stress.fiber_angle_change * kDeg;
        for (int c = 0; c < 3; ++c) sheet[3 * k + c] = o.stress.sheet[c];
        force[k] = 0;
        if (wrinkling) {
          wstate[k] = o.stress.wrinkle_state;
          for (int c = 0; c < 3; ++c) wdir[3 * k + c] = o.stress.wrinkle_dir[c];
        }
      } else {
        smax[k] = smin[k] = angle[k] = 0;
        for (int c = 0; c < 3; ++c) sheet[3 * k + c] = 0;
        for (int c = 0; c < 3; ++c) dmax[3 * k + c] = dmin[3 * k + c] = 0;
        force[k] = o.cable_force;
        if (wrinkling) {
          wstate[k] = 0;
          for (int c = 0; c < 3; ++c) wdir[3 * k + c] = 0;
        }
      }
    }
    const std::uint8_t vt = static_cast<std::uint8_t>(vtk_type(b->type_name()));
    for (int e = 0; e < n; ++e) {
      for (int node : b->nodes(e)) conn.push_back(node);
      offsets.push_back(static_cast<std::int64_t>(conn.size()));
      types.push_back(vt);
    }
    base += n;
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
  xml += "</PointData>\n<CellData>\n";
  xml += app.add("type=\"Float64\" Name=\"true_stress_max\"", smax);
  xml += app.add("type=\"Float64\" Name=\"true_stress_min\"", smin);
  xml += app.add("type=\"Float64\" Name=\"stress_dir_max\" NumberOfComponents=\"3\"", dmax);
  xml += app.add("type=\"Float64\" Name=\"stress_dir_min\" NumberOfComponents=\"3\"", dmin);
  xml += app.add("type=\"Float64\" Name=\"fiber_angle_change\"", angle);
  // Only with membranes (a cables-only frame with it did not read back in meshio: to be found).
  if (std::any_of(model.blocks.begin(), model.blocks.end(),
                  [](const auto& b) { return b->kind() == ElementKind::kMembrane; }))
    xml += app.add("type=\"Float64\" Name=\"sheet_stress\" NumberOfComponents=\"3\"", sheet);
  xml += app.add("type=\"Float64\" Name=\"force\"", force);
  if (wrinkling) {
    xml += app.add("type=\"Int32\" Name=\"wrinkle_state\"", wstate);
    xml += app.add("type=\"Float64\" Name=\"wrinkle_dir\" NumberOfComponents=\"3\"", wdir);
  }
  if (!model.gases.empty()) xml += app.add("type=\"Float64\" Name=\"gas_pressure\"", gas);
  xml += "</CellData>\n<Points>\n";
  xml += app.add("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", flat(model.X));
  xml += "</Points>\n<Cells>\n";
  xml += app.add("type=\"Int64\" Name=\"connectivity\"", conn);
  xml += app.add("type=\"Int64\" Name=\"offsets\"", offsets);
  xml += app.add("type=\"UInt8\" Name=\"types\"", types);
  xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  xml += app.data();
  xml += "\n</AppendedData>\n</VTKFile>\n";

  const std::string name = fmt::format("frame_{:05d}.vtu", frame_times_.size());
  write_file_atomically(dir_ / "frames" / name, xml);
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
  s += fmt::format("  \"frames\": {},\n", frame_times_.size());
  if (r.form_updates >= 0)
    s += fmt::format("  \"form_finding\": {{\"updates\": {}, \"residual\": {}}},\n", r.form_updates,
                     json_number(r.form_residual));
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
