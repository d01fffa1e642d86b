// `velum pattern`: reads the model, flattens its panels, writes the patterns.
#include "velum/run/pattern_command.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <chrono>

#include "run_parts.hpp"
#include "velum/analysis/flatten.hpp"
#include "velum/io/pattern_writer.hpp"
#include "velum/io/roundtrip_model.hpp"
#include "velum/run/commands.hpp"
#include "velum/run/plot_command.hpp"
#include "velum/run/seams_command.hpp"

namespace velum::run {
namespace {

// The panel's triangles (quadrilaterals split along a diagonal, corners only) with the
// section's warp (its first sheet axis) on the shape x at each element's centre; quad4
// elements also as quadrilaterals, flattened for the strain quad4 measures.
PanelMesh panel_mesh(const Model& m, const std::string& set, const NodePositions& x,
                     FlattenSettings& settings) {
  PanelMesh mesh;
  for (const auto& b : m.blocks) {
    if (b->set_name() != set || !b->surface()) continue;
    settings.stiffness = b->sheet_stiffness();  // one section per set
    const int corners = b->shape().corners;
    const bool bilinear = b->type_name() == "quad4";
    for (int e = 0; e < b->size(); ++e) {
      const auto n = b->nodes(e);
      const Vec3 warp = b->output(e, x).stress.axis1;
      const int quad = bilinear ? static_cast<int>(mesh.quads.size()) : -1;
      if (bilinear) mesh.quads.push_back({n[0], n[1], n[2], n[3]});
      mesh.triangles.push_back({n[0], n[1], n[2]});
      mesh.warp.push_back(warp);
      mesh.quad_of.push_back(quad);
      if (corners == 4)
        mesh.triangles.push_back({n[0], n[2], n[3]}), mesh.warp.push_back(warp),
            mesh.quad_of.push_back(quad);
    }
  }
  return mesh;
}

// PDIR/patterns.png through Debian's Python and matplotlib (tools/velum_pattern_sheet.py): a
// drawing for people, so without the interpreter, the script or matplotlib it is skipped with
// a note (the cutting files are written); a failing script is an I/O error.
int draw_sheet(const std::filesystem::path& output) {
  const auto script = share_script("velum_pattern_sheet.py");
  if (!script || access(kPython, X_OK) != 0) {
    say(stderr,
        "velum pattern: note: patterns.png not written: it needs {} with matplotlib and "
        "velum_pattern_sheet.py installed beside velum (share/velum/)\n",
        kPython);
    return kExitOk;
  }
  const int code = run_python(
      "velum pattern",
      {script->string(), (output / "patterns.json").string(), (output / "patterns.png").string()});
  if (code == 3) return kExitOk;  // matplotlib missing: the script said so
  if (code != 0) {
    say(stderr, "error: velum pattern: drawing {} failed (exit {})\n",
        (output / "patterns.png").string(), code);
    return kExitIo;
  }
  return kExitOk;
}

}  // namespace

int pattern_command(const std::filesystem::path& input, const std::filesystem::path& output) {
  std::filesystem::path model_file;
  std::optional<ModelInput> read = read_shape_model(input, "velum pattern", model_file);
  if (!read) return kExitBadInput;
  ModelInput& in = *read;
  std::error_code ec;
  if (!in.patterns.seams.empty()) {
    // Seams first: the model cut into its panels (PDIR/panels.yaml), then flattened.
    std::filesystem::create_directories(output, ec);
    model_file = output / "panels.yaml";
    if (const int code = cut_along_seams(in, input, model_file); code != kExitOk) return code;
    try {
      in = read_model(model_file);
    } catch (const InputError& e) {
      for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
      return kExitBadInput;
    }
  }
  const PatternSettings& ps = in.patterns;
  if (ps.panels.empty()) {
    say(stderr,
        "error: {}: patterns: the model names no panels: add patterns: {{panels: [set, ...], "
        "compensation: [warp, fill]}}\n",
        model_file.string());
    return kExitBadInput;
  }
  const Model& m = in.model;
  // The shape: where the sheet is (the mesh's coordinates, also with reference positions).
  NodePositions x = m.X;
  if (m.U0.size()) x += m.U0;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<io::PatternPanel> panels;
  for (const std::string& name : ps.panels) {
    io::PatternPanel p;
    p.name = name;
    FlattenSettings settings;
    const PanelMesh mesh = panel_mesh(m, name, x, settings);
    if (std::string why = disc_problem(mesh, m.num_nodes()); !why.empty()) {
      say(stderr, "error: {}: patterns.panels: panel '{}' cannot be flattened: {}\n",
          model_file.string(), name, why);
      return kExitBadInput;
    }
    p.flat = flatten_panel(x, mesh, settings);
    for (int n : p.flat.nodes) p.node_ids.push_back(m.node_ids[static_cast<size_t>(n)]);
    io::outline_panel(p, ps.warp, ps.fill, ps.seam_allowance);
    panels.push_back(std::move(p));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    io::write_patterns(output, panels, x, ps.warp, ps.fill, ps.seam_allowance);
    io::write_roundtrip_model(in, x, panels, ps.warp, ps.fill, output / "roundtrip.yaml");
  } catch (const std::runtime_error& e) {
    say(stderr, "error: {}\n", e.what());
    return kExitIo;
  }
  for (const auto& p : panels)
    say(stdout, "panel {}: {} nodes, area 3-D {:.6g}, flat {:.6g}, largest strain {:.3g}\n", p.name,
        p.flat.nodes.size(), p.flat.area_3d, p.flat.area_flat, p.flat.max_strain);
  say(stdout, "velum pattern: {} panel{} flattened in {:.3g} s, written to {}\n", panels.size(),
      panels.size() == 1 ? "" : "s", seconds, output.string());
  return draw_sheet(output);
}

}  // namespace velum::run
