// `velum seams`: the model's surface cut into panels along its seams
// (include/velum/run/seams_command.hpp).
#include "velum/run/seams_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "run_parts.hpp"
#include "velum/analysis/seam_cut.hpp"
#include "velum/io/cut_model.hpp"

namespace velum::run {
namespace {

// The default of patterns.seam_tolerance, in mean element edges.
constexpr double kTolerance = 0.1;

struct SurfaceElement {
  long id;
  int block, e;
  std::vector<int> tris;  // its triangles in the cutter's input
};

// Said on stderr: "error: WHERE: text".
int refuse(const std::string& where, const std::string& text) {
  say(stderr, "error: {}: {}\n", where, text);
  return kExitBadInput;
}

std::string point_text(const Vec3& p) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", p[0], p[1], p[2]);
}

}  // namespace

int cut_along_seams(const ModelInput& in, const std::filesystem::path& model_file,
                    const std::filesystem::path& output) {
  const auto t0 = std::chrono::steady_clock::now();
  const Model& m = in.model;
  const PatternSettings& ps = in.patterns;
  NodePositions x = m.X;
  if (m.U0.size()) x += m.U0;
  // The surface: every membrane element, in the order of their ids; quadrilaterals as two
  // triangles, higher-order elements on their corners.
  std::vector<SurfaceElement> elements;
  for (size_t b = 0; b < m.blocks.size(); ++b) {
    const auto& blk = *m.blocks[b];
    if (!blk.surface()) continue;
    if (blk.sliding())
      return refuse(model_file.string(), "velum seams: sliding cables are not cut");
    for (int e = 0; e < blk.size(); ++e)
      elements.push_back({in.element_ids[b][static_cast<size_t>(e)], static_cast<int>(b), e, {}});
  }
  if (elements.empty())
    return refuse(model_file.string(), "patterns.seams: the model has no membrane elements to cut");
  std::sort(elements.begin(), elements.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  std::vector<std::array<int, 3>> tris;
  for (auto& el : elements) {
    const auto n = m.blocks[static_cast<size_t>(el.block)]->nodes(el.e);
    el.tris.push_back(static_cast<int>(tris.size()));
    tris.push_back({n[0], n[1], n[2]});
    if (m.blocks[static_cast<size_t>(el.block)]->shape().corners == 4) {
      el.tris.push_back(static_cast<int>(tris.size()));
      tris.push_back({n[0], n[2], n[3]});
    }
  }
  SeamCutter cut(x, tris, ps.seam_snap);
  // Nodes that stay: those of node sets (supports, loads) and of lines (cables).
  for (const auto& [name, nodes] : in.node_sets)
    for (int n : nodes) cut.fix(n);
  for (const auto& blk : m.blocks)
    if (!blk->surface())
      for (int e = 0; e < blk->size(); ++e)
        for (int n : blk->nodes(e)) cut.fix(n);
  if (!cut.surface().problem().empty())
    return refuse(model_file.string(),
                  "patterns.seams: the surface is not a manifold: " + cut.surface().problem());
  const double tolerance =
      ps.seam_tolerance > 0 ? ps.seam_tolerance : kTolerance * cut.surface().mean_edge();
  const double snap =
      kTolerance * cut.surface().mean_edge();  // a point this close to a node is the node
  auto node_id = [&](int n) { return n < m.num_nodes() ? m.node_ids[static_cast<size_t>(n)] : -1; };
  double length = 0;
  int flips = 0;
  for (size_t i = 0; i < ps.seams.size(); ++i) {
    const auto& seam = ps.seams[i];
    if (seam.path) {
      try {
        cut.add_node_path(seam.nodes, static_cast<int>(i));
      } catch (const SeamError& e) {
        return refuse(seam.where + ".nodes",
                      fmt::format("nodes {} and {} are not joined by an element edge: a seam along "
                                  "nodes follows element edges",
                                  node_id(e.a), node_id(e.b)));
      }
      continue;
    }
    std::vector<SurfacePoint> at;
    for (size_t k = 0; k < seam.nodes.size(); ++k) {
      SurfacePoint p;
      if (seam.nodes[k] >= 0) {
        if (cut.surface().faces_at(seam.nodes[k]).empty())
          return refuse(
              fmt::format("{}.points[{}]", seam.where, k),
              fmt::format("node {} is not a node of a membrane element", node_id(seam.nodes[k])));
        p.vertex = seam.nodes[k];
      } else {
        double d = 0;
        p = locate(cut.surface(), seam.points[k], snap, &d);
        if (!(d <= tolerance))
          return refuse(
              fmt::format("{}.points[{}]", seam.where, k),
              fmt::format("{} lies {:.4g} off the shape, farther than patterns.seam_tolerance "
                          "{:.4g}: a seam's points are on the surface",
                          point_text(seam.points[k]), d, tolerance));
      }
      if (p.kind == SurfacePoint::Kind::Face) {
        if (k == 0 || k + 1 == seam.nodes.size())
          return refuse(
              fmt::format("{}.points[{}]", seam.where, k),
              fmt::format("{} lies inside the surface, not on its boundary, on another seam "
                          "or at a node: a seam ends where it closes a panel",
                          point_text(seam.points[k])));
        // A point the seam passes on its way: on the nearest edge of its element.
        p = locate(cut.surface(), seam.points[k], HUGE_VAL, nullptr);
      }
      at.push_back(p);
    }
    for (size_t k = 0; k + 1 < at.size(); ++k) {
      try {
        const SurfacePath path = cut.add_geodesic(at[k], at[k + 1], static_cast<int>(i));
        length += path.length, flips += path.flips;
      } catch (const std::invalid_argument& e) {
        return refuse(fmt::format("{}.points", seam.where), e.what());
      }
    }
  }
  int count = 0;
  std::vector<int> panel;
  try {
    panel = cut.panels(&count);
  } catch (const SeamError& e) {
    const Vec3 at = cut.surface().x().col(e.a);
    return refuse(
        ps.seams[static_cast<size_t>(e.seam)].where,
        fmt::format("the seam does not close a panel: it has the same panel on both sides "
                    "at {}; a seam runs from the boundary (or another seam) to the boundary "
                    "(or another seam)",
                    point_text(at)));
  }
  const double cut_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<std::string> names = ps.panels;
  if (!names.empty() && static_cast<int>(names.size()) != count)
    return refuse(ps.panels_where, fmt::format("the seams cut the surface into {} panel{}, and "
                                               "patterns.panels names {}",
                                               count, count == 1 ? "" : "s", names.size()));
  for (int k = static_cast<int>(names.size()); k < count; ++k)
    names.push_back(fmt::format("panel_{}", k + 1));
  // The mesh written: the model's nodes and those the seams made.
  io::CutMesh mesh;
  mesh.x = cut.surface().x();
  mesh.node_ids = m.node_ids;
  long next_node = *std::max_element(m.node_ids.begin(), m.node_ids.end()) + 1;
  for (size_t k = 0; k < cut.new_nodes().size(); ++k) mesh.node_ids.push_back(next_node++);
  long next_element = 0;
  for (const auto& ids : in.element_ids)
    for (long id : ids) next_element = std::max(next_element, id + 1);
  // Triangles by the input triangle they came from.
  std::vector<std::vector<int>> pieces(tris.size());
  for (size_t f = 0; f < cut.triangles().size(); ++f)
    pieces[static_cast<size_t>(cut.parent()[f])].push_back(static_cast<int>(f));
  std::vector<std::vector<io::CutMesh::Element>> by_panel(static_cast<size_t>(count));
  std::vector<std::set<std::string>> sets_of(static_cast<size_t>(count));
  for (const auto& el : elements) {
    const auto& blk = *m.blocks[static_cast<size_t>(el.block)];
    std::vector<int> now;
    bool changed = false;
    for (int t : el.tris)
      for (int f : pieces[static_cast<size_t>(t)])
        now.push_back(f), changed = changed || cut.split()[static_cast<size_t>(f)];
    int p0 = panel[static_cast<size_t>(now[0])];
    for (int f : now) changed = changed || panel[static_cast<size_t>(f)] != p0;
    if (!changed) {
      io::CutMesh::Element out{el.id, std::string(blk.shape().name), {}};
      for (int n : blk.nodes(el.e)) out.nodes.push_back(mesh.node_ids[static_cast<size_t>(n)]);
      by_panel[static_cast<size_t>(p0)].push_back(std::move(out));
      sets_of[static_cast<size_t>(p0)].insert(blk.set_name());
      continue;
    }
    if (blk.shape().nodes != blk.shape().corners)
      return refuse(
          model_file.string(),
          fmt::format("patterns.seams: a seam crosses element {} ({}): velum seams splits tri3 "
                      "and quad4 elements; give the seam along element edges (nodes:) or mesh "
                      "with tri3",
                      el.id, blk.shape().name));
    bool first = true;
    for (int f : now) {
      const auto& t = cut.triangles()[static_cast<size_t>(f)];
      io::CutMesh::Element out{first ? el.id : next_element++, "tri3", {}};
      for (int n : t) out.nodes.push_back(mesh.node_ids[static_cast<size_t>(n)]);
      const int p = panel[static_cast<size_t>(f)];
      by_panel[static_cast<size_t>(p)].push_back(std::move(out));
      sets_of[static_cast<size_t>(p)].insert(blk.set_name());
      first = false;
    }
  }
  for (int p = 0; p < count; ++p) {
    const auto& sets = sets_of[static_cast<size_t>(p)];
    if (sets.size() > 1)
      return refuse(
          model_file.string(),
          fmt::format("patterns.seams: panel '{}' holds elements of the sets '{}' and '{}': "
                      "a panel is one fabric: add a seam between them",
                      names[static_cast<size_t>(p)], *sets.begin(), *std::next(sets.begin())));
    mesh.renamed[*sets.begin()].push_back(names[static_cast<size_t>(p)]);
    mesh.sets.emplace_back(names[static_cast<size_t>(p)],
                           std::move(by_panel[static_cast<size_t>(p)]));
  }
  mesh.panels = names;
  // Lines (cables) as they are; one along an edge a seam ended on is split at the new node.
  std::map<std::pair<int, int>, int> made_on;  // edge (min, max) -> new node
  for (size_t k = 0; k < cut.new_nodes().size(); ++k)
    made_on[{cut.new_nodes()[k].a, cut.new_nodes()[k].b}] =
        cut.original_nodes() + static_cast<int>(k);
  std::map<std::string, size_t> line_set;
  for (size_t b = 0; b < m.blocks.size(); ++b) {
    const auto& blk = *m.blocks[b];
    if (blk.surface()) continue;
    if (!line_set.count(blk.set_name()))
      line_set[blk.set_name()] = mesh.sets.size(),
      mesh.sets.emplace_back(blk.set_name(), std::vector<io::CutMesh::Element>{});
    auto& list = mesh.sets[line_set[blk.set_name()]].second;
    for (int e = 0; e < blk.size(); ++e) {
      const auto n = blk.nodes(e);
      io::CutMesh::Element out{
          in.element_ids[b][static_cast<size_t>(e)], std::string(blk.shape().name), {}};
      auto it = n.size() == 2 ? made_on.find({std::min(n[0], n[1]), std::max(n[0], n[1])})
                              : made_on.end();
      if (it != made_on.end()) {
        list.push_back({out.id,
                        out.type,
                        {mesh.node_ids[static_cast<size_t>(n[0])],
                         mesh.node_ids[static_cast<size_t>(it->second)]}});
        list.push_back({next_element++,
                        out.type,
                        {mesh.node_ids[static_cast<size_t>(it->second)],
                         mesh.node_ids[static_cast<size_t>(n[1])]}});
        continue;
      }
      for (int k : n) out.nodes.push_back(mesh.node_ids[static_cast<size_t>(k)]);
      list.push_back(std::move(out));
    }
  }
  // Node sets as lists; a new node on an edge of a set's two nodes joins the set.
  for (const auto& [name, nodes] : in.node_sets) {
    std::set<int> members(nodes.begin(), nodes.end());
    auto& ids = mesh.node_sets[name];
    for (int n : nodes) ids.push_back(m.node_ids[static_cast<size_t>(n)]);
    for (size_t k = 0; k < cut.new_nodes().size(); ++k)
      if (members.count(cut.new_nodes()[k].a) && members.count(cut.new_nodes()[k].b))
        ids.push_back(mesh.node_ids[static_cast<size_t>(cut.original_nodes()) + k]);
  }
  try {
    io::write_cut_model(in, mesh, output);
  } catch (const std::runtime_error& e) {
    say(stderr, "error: {}\n", e.what());
    return kExitIo;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  try {
    (void)read_model(output);
  } catch (const InputError& e) {
    for (const auto& msg : e.messages())
      say(stderr, "error: the model velum seams wrote: {}\n", msg);
    return kExitBadInput;
  }
  double original = M_PI;
  for (const auto& t : tris)
    original = std::min(original, smallest_angle(x.col(t[0]), x.col(t[1]), x.col(t[2])));
  for (int p = 0; p < count; ++p)
    say(stdout, "panel {}: {} elements\n", names[static_cast<size_t>(p)],
        mesh.sets[static_cast<size_t>(p)].second.size());
  say(stdout,
      "velum seams: {} seam{} ({:.6g} long as geodesics, {} strip moves), {} panel{}, {} new "
      "node{}, {} moved onto a seam; smallest triangle angle {:.1f} deg (the mesh's {:.1f}); "
      "cut in {:.3g} s, written in {:.3g} s to {}\n",
      ps.seams.size(), ps.seams.size() == 1 ? "" : "s", length, flips, count, count == 1 ? "" : "s",
      cut.new_nodes().size(), cut.new_nodes().size() == 1 ? "" : "s", cut.moved(),
      std::min(cut.smallest_new_angle(), original) * 180 / M_PI, original * 180 / M_PI, cut_seconds,
      seconds - cut_seconds, output.string());
  return kExitOk;
}

std::optional<ModelInput> read_shape_model(const std::filesystem::path& input,
                                           const std::string& command,
                                           std::filesystem::path& model_file) {
  model_file = input;
  std::error_code ec;
  if (std::filesystem::is_directory(input, ec)) {
    model_file = input / "form.yaml";
    if (!std::filesystem::exists(model_file, ec)) {
      say(stderr,
          "error: {}: a results folder gives its shape to `{}` through its found form "
          "(form.yaml, written by form finding), and it has none: give the model file\n",
          input.string(), command);
      return std::nullopt;
    }
  }
  try {
    return read_model(model_file);
  } catch (const InputError& e) {
    for (const auto& msg : e.messages()) say(stderr, "error: {}\n", msg);
    return std::nullopt;
  }
}

int seams_command(const std::filesystem::path& input, const std::filesystem::path& output) {
  std::filesystem::path model_file;
  std::optional<ModelInput> read = read_shape_model(input, "velum seams", model_file);
  if (!read) return kExitBadInput;
  ModelInput& in = *read;
  if (in.patterns.seams.empty()) {
    say(stderr,
        "error: {}: patterns.seams: the model gives no seams: add patterns: {{seams: [{{points: "
        "[[x, y, z], [x, y, z]]}}, {{nodes: [id, id, ...]}}]}}\n",
        model_file.string());
    return kExitBadInput;
  }
  return cut_along_seams(in, model_file, output);
}

}  // namespace velum::run
