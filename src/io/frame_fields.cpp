#include "velum/io/frame_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace velum::io {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;
constexpr double kAbsent = std::numeric_limits<double>::quiet_NaN();

struct Spec {
  CellField field;
  const char* name;
  int components;
  bool averaged;
};

// The arrays in the order they appear in a frame (the first six as before issue 20).
constexpr Spec kSpecs[] = {
    {kTrueStressMax, "true_stress_max", 1, true},
    {kTrueStressMin, "true_stress_min", 1, true},
    {kStressDirMax, "stress_dir_max", 3, false},
    {kStressDirMin, "stress_dir_min", 3, false},
    {kFiberAngleChange, "fiber_angle_change", 1, true},
    {kCableForce, "force", 1, false},
    {kStress11, "stress_11", 1, true},
    {kStress22, "stress_22", 1, true},
    {kStress12, "stress_12", 1, true},
    {kForcePerLengthMax, "force_per_length_max", 1, true},
    {kForcePerLengthMin, "force_per_length_min", 1, true},
    {kForcePerLength11, "force_per_length_11", 1, true},
    {kForcePerLength22, "force_per_length_22", 1, true},
    {kForcePerLength12, "force_per_length_12", 1, true},
    {kStrain11, "strain_11", 1, true},
    {kStrain22, "strain_22", 1, true},
    {kStrain12, "strain_12", 1, true},
    {kStretchMax, "stretch_max", 1, true},
    {kStretchMin, "stretch_min", 1, true},
    {kSheetAxis1, "sheet_axis_1", 3, false},
    {kSheetAxis2, "sheet_axis_2", 3, false},
    {kSheetNormal, "sheet_normal", 3, false},
    {kFiberDir1, "fiber_dir_1", 3, false},
    {kFiberDir2, "fiber_dir_2", 3, false},
    {kWrinkleDir, "wrinkle_dir", 3, false},
};

void put(CellArray& a, size_t k, double v) {
  a.values[k] = v;
}
void put(CellArray& a, size_t k, const Vec3& v) {
  for (int c = 0; c < 3; ++c) a.values[3 * k + c] = v[c];
}

}  // namespace

FrameFields evaluate_cells(const Model& model, const NodePositions& x,
                           const std::vector<std::vector<int>>& own, bool extremes_only) {
  // One value per listed cell (compact: a process holds no whole-mesh array for its piece).
  size_t ne = 0;
  for (const auto& mine : own) ne += mine.size();
  // Extremes only (a run without frames): the three arrays they read hold values, the others
  // none (at Hencky n = 130, 1.2 MB of arrays at each output instead of 15 MB).
  auto any_block = [&](auto has) {  // a sheet's property that adds a frame array
    return !extremes_only &&
           std::any_of(model.blocks.begin(), model.blocks.end(),
                       [&](const auto& b) { return b->surface() && has(*b->surface()); });
  };
  const bool wrinkling = any_block([](const auto& sf) { return sf.tension_field(); });
  FrameFields f;
  f.cells.reserve(kCellFieldCount);
  for (const Spec& s : kSpecs) {
    if (s.field == kWrinkleDir && !wrinkling) continue;
    const bool read =
        s.field == kTrueStressMax || s.field == kForcePerLengthMax || s.field == kCableForce;
    const size_t size = extremes_only && !read ? 0 : ne * static_cast<size_t>(s.components);
    f.cells.push_back({s.name, s.components, std::vector<double>(size, kAbsent), s.averaged});
  }
  if (wrinkling) f.wrinkle_state.assign(ne, 0);
  // The current thickness, only where a law thins the sheet (an incompressible one): the
  // frames of the other models stay as they were.
  const bool thinning = any_block([](const auto& sf) { return sf.thins(); });
  const size_t thickness_at = f.cells.size();
  if (thinning) f.cells.push_back({"thickness", 1, std::vector<double>(ne, kAbsent), true});
  // The equivalent plastic strain, only where a law yields.
  const bool yielding = any_block([](const auto& sf) { return sf.yields(); });
  const size_t plastic_at = f.cells.size();
  if (yielding) f.cells.push_back({"plastic_strain", 1, std::vector<double>(ne, kAbsent), true});
  auto& c = f.cells;
  size_t base = 0;
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const ElementBlock& blk = *model.blocks[bi];
    const std::vector<int>& mine = own[bi];
    const int count = static_cast<int>(mine.size());
    if (blk.kind() == ElementKind::kCable) {
#pragma omp parallel for schedule(static)
      for (int i = 0; i < count; ++i)
        put(c[kCableForce], base + static_cast<size_t>(i), blk.output(mine[i], x).cable_force);
      base += static_cast<size_t>(count);
      continue;
    }
#pragma omp parallel for schedule(static)
    for (int i = 0; i < count; ++i) {
      const int e = mine[i];
      const ElementOutput o = blk.output(e, x);
      const MembraneStress& s = o.stress;
      const size_t k = base + static_cast<size_t>(i);
      const double t = o.thickness;
      if (extremes_only) {
        put(c[kTrueStressMax], k, s.max);
        put(c[kForcePerLengthMax], k, t * s.max);
        continue;
      }
      put(c[kTrueStressMax], k, s.max);
      put(c[kTrueStressMin], k, s.min);
      put(c[kStressDirMax], k, s.dir_max);
      put(c[kStressDirMin], k, s.dir_min);
      put(c[kFiberAngleChange], k, s.fiber_angle_change * kDegreesPerRadian);
      put(c[kStress11], k, s.sheet[0]);
      put(c[kStress22], k, s.sheet[1]);
      put(c[kStress12], k, s.sheet[2]);
      put(c[kForcePerLengthMax], k, t * s.max);
      put(c[kForcePerLengthMin], k, t * s.min);
      put(c[kForcePerLength11], k, t * s.sheet[0]);
      put(c[kForcePerLength22], k, t * s.sheet[1]);
      put(c[kForcePerLength12], k, t * s.sheet[2]);
      put(c[kStrain11], k, s.strain[0]);
      put(c[kStrain22], k, s.strain[1]);
      put(c[kStrain12], k, s.strain[2]);
      put(c[kStretchMax], k, s.stretch_max);
      put(c[kStretchMin], k, s.stretch_min);
      put(c[kSheetAxis1], k, s.axis1);
      put(c[kSheetAxis2], k, s.axis2);
      put(c[kSheetNormal], k, s.normal);
      put(c[kFiberDir1], k, s.axis1);
      put(c[kFiberDir2], k, s.fiber2);
      if (wrinkling) {
        put(c[kWrinkleDir], k, s.wrinkle_dir);
        f.wrinkle_state[k] = s.wrinkle_state;
      }
      if (thinning) put(c[thickness_at], k, o.current_thickness);
      if (yielding) put(c[plastic_at], k, o.plastic_strain);
    }
    base += static_cast<size_t>(count);
  }
  return f;
}

CellLabels cell_labels(const Model& model, const std::vector<std::string>& block_materials) {
  CellLabels l;
  auto index = [](std::vector<std::string>& names, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) return static_cast<std::int32_t>(it - names.begin());
    names.push_back(name);
    return static_cast<std::int32_t>(names.size() - 1);
  };
  for (size_t b = 0; b < model.blocks.size(); ++b) {
    l.set_of_block.push_back(index(l.sets, model.blocks[b]->set_name()));
    l.material_of_block.push_back(
        index(l.materials, b < block_materials.size() ? block_materials[b] : std::string()));
  }
  return l;
}

NodalAverage::NodalAverage(const Model& model, const std::vector<std::vector<int>>& own)
    : node_weight(static_cast<size_t>(model.num_nodes()), 0.0) {
  for (const auto& mine : own) cell_weight.resize(cell_weight.size() + mine.size(), 0.0);
  size_t first = 0;  // the block's first listed cell
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = model.blocks[bi];
    if (b->kind() == ElementKind::kMembrane)
      for (size_t i = 0; i < own[bi].size(); ++i) {
        const int e = own[bi][i];
        const size_t k = first + i;
        cell_weight[k] = b->measure(e);
        for (int node : b->nodes(e)) node_weight[static_cast<size_t>(node)] += cell_weight[k];
      }
    first += own[bi].size();
  }
}

std::vector<double> NodalAverage::sums(const Model& model, const std::vector<std::vector<int>>& own,
                                       const std::vector<double>& cell) const {
  std::vector<double> sum(node_weight.size(), 0.0);
  size_t first = 0;
  for (size_t bi = 0; bi < model.blocks.size(); ++bi) {
    const auto& b = model.blocks[bi];
    for (size_t i = 0; i < own[bi].size(); ++i) {
      const size_t k = first + i;
      if (cell_weight[k] == 0) continue;
      const double wv = cell_weight[k] * cell[k];
      for (int node : b->nodes(own[bi][i])) sum[static_cast<size_t>(node)] += wv;
    }
    first += own[bi].size();
  }
  return sum;
}

void NodalAverage::divide(std::vector<double>& sum) const {
  for (size_t n = 0; n < sum.size(); ++n)
    sum[n] = node_weight[n] > 0 ? sum[n] / node_weight[n] : kAbsent;
}

}  // namespace velum::io
