#include "velum/io/frame_writer.hpp"

#include <fmt/format.h>

#include <system_error>

#include "velum/io/results_writer.hpp"
#include "velum/parallel/model_piece.hpp"

namespace velum::io {
namespace {

// Appended raw binary: each array is a UInt64 byte count followed by the values. The arrays
// are laid out last first: meshio (5.0) reads raw appended data by finding each array's tag
// by its offset while rewriting the offsets of those it has read, and with ascending offsets
// it can find a rewritten tag instead (a CorruptionError on frames with many arrays); in
// reverse order the tag it looks for always precedes the rewritten ones.
class Appended {
 public:
  template <class T>
  std::string add(const std::string& attrs, const std::vector<T>& v) {
    declared_ += fmt::format("<PDataArray {}/>\n", attrs);
    const std::string tag = fmt::format("<DataArray {} format=\"appended\" offset=\"{}{}\"/>\n",
                                        attrs, kMark, chunks_.size());
    const std::uint64_t bytes = v.size() * sizeof(T);
    std::string& c = chunks_.emplace_back();
    c.reserve(sizeof bytes + bytes);
    c.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    c.append(reinterpret_cast<const char*>(v.data()), bytes);
    return tag;
  }
  /// The PDataArray declarations of the arrays added since the last call (for a .pvtu).
  std::string declared() { return std::exchange(declared_, {}); }
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
  std::string declared_;
};

std::string frame_name(int index) {
  return fmt::format("frame_{:05d}", index);
}

}  // namespace

FrameWriter::FrameWriter(const ModelInput& input, std::filesystem::path results,
                         const Assembler& assembler, int rank, int pieces)
    : input_(input),
      dir_(std::move(results)),
      rank_(rank),
      pieces_(pieces),
      labels_(cell_labels(input.model, input.block_materials)),
      own_(assembler.own_by_block()),
      average_(input.model, own_) {
  const Model& model = input.model;
  const auto& own = own_;
  const int nn = model.num_nodes();
  // The piece's points: the nodes of its elements; on the first process also the nodes no
  // element holds, so that the pieces together hold every node. Each point's index in the
  // one-process frame is its node's in the whole model.
  std::vector<std::int64_t> local(static_cast<size_t>(nn), -1);
  std::vector<char> used(static_cast<size_t>(nn), pieces > 1 ? 0 : 1);
  if (const ModelPiece* piece = model.piece.get()) {
    for (size_t bi = 0; bi < model.blocks.size(); ++bi)
      for (int e : own[bi])
        for (int n : model.blocks[bi]->nodes(e)) used[static_cast<size_t>(n)] = 1;
    for (int n : piece->bare) used[static_cast<size_t>(n)] = 1;
  }
  for (int n = 0; n < nn; ++n)
    if (used[static_cast<size_t>(n)]) {
      local[static_cast<size_t>(n)] = static_cast<std::int64_t>(nodes_.size());
      nodes_.push_back(n);
      if (model.piece) node_index_.push_back(model.piece->global_node[static_cast<size_t>(n)]);
    }
  std::int64_t first = 0;  // the block's first cell in the one-process order
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = model.blocks[bi];
    const auto vt = static_cast<std::uint8_t>(b->shape().vtk);
    for (int e : own[bi]) {
      for (int node : b->nodes(e)) conn_.push_back(local[static_cast<size_t>(node)]);
      offsets_.push_back(static_cast<std::int64_t>(conn_.size()));
      types_.push_back(vt);
      element_id_.push_back(input.element_ids[bi][static_cast<size_t>(e)]);
      cells_.push_back(first + e);
      set_index_.push_back(labels_.set_of_block[bi]);
      material_index_.push_back(labels_.material_of_block[bi]);
    }
    first += b->size();
  }
}

std::vector<std::vector<double>> FrameWriter::average_to_nodes(const FrameFields& f,
                                                               const Assembler& assembler) const {
  if (!weights_complete_) {  // on first use: the constructor is not a collective call
    const std::pair<double*, int> weights[] = {{average_.node_weight.data(), 1}};
    assembler.sum_at_shared_nodes(weights);
    weights_complete_ = true;
  }
  std::vector<std::vector<double>> out;
  for (const CellArray& a : f.cells)
    if (a.averaged) out.push_back(average_.sums(input_.model, own_, a.values));
  std::vector<std::pair<double*, int>> arrays;
  for (auto& sum : out) arrays.emplace_back(sum.data(), 1);
  assembler.sum_at_shared_nodes(arrays);
  for (auto& sum : out) average_.divide(sum);
  return out;
}

std::string FrameWriter::file(int index) const {
  return file(index, pieces_);
}

std::string FrameWriter::file(int index, int pieces) {
  return fmt::format("frames/{}.{}", frame_name(index), pieces > 1 ? "pvtu" : "vtu");
}

void FrameWriter::write(int index, const FrameValues& v) const {
  const Model& model = input_.model;
  const bool piece = pieces_ > 1;
  auto points = [&](const NodePositions& M) {
    std::vector<double> out;
    out.reserve(3 * nodes_.size());
    for (std::int64_t n : nodes_) out.insert(out.end(), M.col(n).data(), M.col(n).data() + 3);
    return out;
  };
  auto at_nodes = [&](const auto& all) {
    std::vector<typename std::decay_t<decltype(all)>::value_type> out;
    out.reserve(nodes_.size());
    for (std::int64_t n : nodes_) out.push_back(all[static_cast<size_t>(n)]);
    return out;
  };
  // The piece's cells of an array over every cell (the frame's cell fields hold the piece's
  // cells already, in its order).
  auto at_cells = [&](const auto& all, int components) {
    std::vector<typename std::decay_t<decltype(all)>::value_type> out;
    out.reserve(cells_.size() * static_cast<size_t>(components));
    for (std::int64_t c : cells_)
      for (int k = 0; k < components; ++k) out.push_back(all[c * components + k]);
    return out;
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
      app.add("type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\"", std::vector<double>{v.t}));
  app.declared();
  xml += fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", nodes_.size(),
                     cells_.size());
  xml += "<PointData Vectors=\"displacement\">\n";
  xml += app.add("type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"", points(v.U));
  xml += app.add("type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"", points(v.V));
  xml += app.add("type=\"Float64\" Name=\"reaction\" NumberOfComponents=\"3\"", points(v.R));
  xml += app.add("type=\"Int64\" Name=\"node_id\"", at_nodes(model.node_ids));
  if (piece) xml += app.add("type=\"Int64\" Name=\"node_index\"", node_index_);
  size_t averaged = 0;
  for (const CellArray& a : v.f.cells)
    if (a.averaged)
      xml += app.add(fmt::format("type=\"Float64\" Name=\"{}\"", a.name),
                     at_nodes(v.averaged[averaged++]));
  if (v.node_fields)
    for (const auto& [name, values] : *v.node_fields)
      xml += app.add(fmt::format("type=\"Float64\" Name=\"{}\"", name), at_nodes(values));
  const std::string point_arrays = app.declared();
  xml += "</PointData>\n<CellData>\n";
  for (const CellArray& a : v.f.cells)  // scalars without NumberOfComponents: (n,) in meshio
    xml += app.add(a.components == 1
                       ? fmt::format("type=\"Float64\" Name=\"{}\"", a.name)
                       : fmt::format("type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\"",
                                     a.name, a.components),
                   a.values);
  if (!v.f.wrinkle_state.empty())
    xml += app.add("type=\"Int32\" Name=\"wrinkle_state\"", v.f.wrinkle_state);
  xml += app.add("type=\"Int32\" Name=\"element_set\"", set_index_);
  xml += app.add("type=\"Int32\" Name=\"material\"", material_index_);
  xml += app.add("type=\"Int64\" Name=\"element_id\"", element_id_);
  if (piece) xml += app.add("type=\"Int64\" Name=\"cell_index\"", cells_);
  if (!v.gas.empty()) xml += app.add("type=\"Float64\" Name=\"gas_pressure\"", at_cells(v.gas, 1));
  const std::string cell_arrays = app.declared();
  xml += "</CellData>\n<Points>\n";
  xml += app.add("type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"", points(model.X));
  const std::string point_coordinates = app.declared();
  xml += "</Points>\n<Cells>\n";
  xml += app.add("type=\"Int64\" Name=\"connectivity\"", conn_);
  xml += app.add("type=\"Int64\" Name=\"offsets\"", offsets_);
  xml += app.add("type=\"UInt8\" Name=\"types\"", types_);
  xml += "</Cells>\n</Piece>\n</UnstructuredGrid>\n";

  const std::string name = frame_name(index);
  if (!piece) {
    write_file_atomically(dir_ / "frames" / (name + ".vtu"), app.finish(xml));
    return;
  }
  const std::filesystem::path folder = dir_ / "frames" / name;
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) throw OutputError(fmt::format("cannot create {}: {}", folder.string(), ec.message()));
  write_file_atomically(folder / fmt::format("{}_{}.vtu", name, rank_), app.finish(xml));
  if (rank_ == 0) {
    std::string p =
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PUnstructuredGrid "
        "GhostLevel=\"0\">\n";
    p += "<PPointData Vectors=\"displacement\">\n" + point_arrays + "</PPointData>\n";
    p += "<PCellData>\n" + cell_arrays + "</PCellData>\n";
    p += "<PPoints>\n" + point_coordinates + "</PPoints>\n";
    for (int k = 0; k < pieces_; ++k)
      p += fmt::format("<Piece Source=\"{0}/{0}_{1}.vtu\"/>\n", name, k);
    p += "</PUnstructuredGrid>\n</VTKFile>\n";
    write_file_atomically(dir_ / "frames" / (name + ".pvtu"), p);
  }
}

}  // namespace velum::io
