// The frames of the ParaView series (docs/model-format.md, "Frames"). On one
// process a frame is the whole mesh in frames/frame_NNNNN.vtu. Under mpirun (docs/parallel.md)
// each process writes the piece of its own elements, with the nodes they use, in
// frames/frame_NNNNN/frame_NNNNN_K.vtu (K its rank; the first process's piece also holds the
// nodes no element uses), and the first process writes frames/frame_NNNNN.pvtu naming the
// pieces: results.pvd lists the .pvtu files. The pieces carry two arrays more, `node_index`
// and `cell_index`: each point's and cell's position in the one-process frame.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "velum/assembly/assembler.hpp"
#include "velum/io/frame_fields.hpp"
#include "velum/io/model_reader.hpp"

namespace velum::io {

/// The values of one frame, whole mesh (node and cell order of the model).
struct FrameValues {
  double t = 0;
  const NodePositions& U;  ///< displacements
  const NodePositions& V;  ///< velocities
  const NodePositions& R;  ///< reactions
  const FrameFields& f;
  /// Point values of f's averaged arrays, in their order (FrameWriter::average_to_nodes).
  const std::vector<std::vector<double>>& averaged;
  const std::vector<double>& gas;  ///< per cell: absolute gas pressure (empty: no gas)
  /// Point fields of the loads (contact_pressure, contact_gap), one value per node; may be null.
  const std::vector<std::pair<std::string, std::vector<double>>>* node_fields = nullptr;
};

class FrameWriter {
 public:
  /// The piece of the elements `assembler` computes (every element on one process); `rank`
  /// of `pieces` processes. `results` is the results folder.
  FrameWriter(const ModelInput& input, std::filesystem::path results, const Assembler& assembler,
              int rank, int pieces);
  /// The point values of f's averaged cell arrays (in their order), complete at this piece's
  /// nodes: this process's cells' sums, completed at the nodes shared with other processes
  /// (their sums only are exchanged). A collective call.
  std::vector<std::vector<double>> average_to_nodes(const FrameFields& f,
                                                    const Assembler& assembler) const;
  /// Writes this process's file of frame `index` (and on the first of several processes the
  /// .pvtu). Throws OutputError.
  void write(int index, const FrameValues& v) const;
  /// The file of frame `index` that results.pvd names, relative to the results folder.
  std::string file(int index) const;
  /// The same for a run on `pieces` processes (1: one .vtu per frame, more: a .pvtu each).
  static std::string file(int index, int pieces);

 private:
  const ModelInput& input_;
  std::filesystem::path dir_;  // results folder
  int rank_, pieces_;
  CellLabels labels_;
  std::vector<std::vector<int>> own_;  // per block, the piece's elements (a copy: a staged run
                                       // makes a new system for each step)
  mutable NodalAverage average_;       // node weights completed on first use
  mutable bool weights_complete_ = false;
  // The piece's topology (fixed): its nodes (model indices, ascending) and cells (indices in
  // the one-process cell order) with their connectivity in piece-local node numbers; on
  // several processes each point's node in the whole model (node_index).
  std::vector<std::int64_t> nodes_, cells_, node_index_;
  std::vector<std::int64_t> conn_, offsets_, element_id_;
  std::vector<std::int32_t> set_index_, material_index_;
  std::vector<std::uint8_t> types_;
};

}  // namespace velum::io
