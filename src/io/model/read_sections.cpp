// Reads sections: (an element set, its material, thickness or area, sheet axes) and builds
// the element blocks.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reader.hpp"
#include "shape_checks.hpp"

namespace velum::io::model_file {

void Reader::parse_sections(const Node& ss) {
  if (!ss.IsSequence()) {
    error(ss, "sections", "expected a list of {elements, material, ...}");
    return;
  }
  for (size_t i = 0; i < ss.size(); ++i) {
    const Node s = ss[i];
    const std::string p = item("sections", i);
    if (!check_map(s, p,
                   {"elements", "material", "thickness", "area", "axes", "integration", "wrinkling",
                    "wrinkling_stiffness", "prestress", "friction", "reefing", "cut_time"}))
      continue;
    auto set = text(s, "elements", p, true);
    auto mat = text(s, "material", p, true);
    if (!set || !mat) continue;
    auto sit = element_sets_.find(*set);
    if (sit == element_sets_.end()) {
      if (mesh_ok_)
        error(s["elements"], sub(p, "elements"),
              fmt::format("undefined element set '{}'{}", *set,
                          suggestion(*set, keys_of(element_sets_))));
      continue;
    }
    ElementSet& es = sit->second;
    if (es.has_section) {
      error(s["elements"], sub(p, "elements"),
            fmt::format("element set '{}' already has a section", *set));
      continue;
    }
    es.has_section = true;
    auto mit = materials_.find(*mat);
    if (mit == materials_.end()) {
      error(s["material"], sub(p, "material"),
            fmt::format("undefined material '{}'{}", *mat, suggestion(*mat, keys_of(materials_))));
      continue;
    }
    const MaterialDef& md = mit->second;
    const bool membrane = es.dimension == 2;
    if (membrane && md.cable) {
      error(s["material"], sub(p, "material"),
            fmt::format("set '{}' holds membrane elements but material '{}' is a cable law", *set,
                        *mat));
      continue;
    }
    if (!membrane && !md.cable && !md.type.empty()) {
      error(s["material"], sub(p, "material"),
            fmt::format("set '{}' holds cable elements but material '{}' is a membrane law "
                        "(use type: cable)",
                        *set, *mat));
      continue;
    }
    std::optional<double> size;
    if (membrane) {
      if (has(s, "area"))
        error(s["area"], sub(p, "area"), "membranes take a thickness, not an area");
      size = positive(s, "thickness", p, true, "the thickness");
    } else {
      if (has(s, "thickness"))
        error(s["thickness"], sub(p, "thickness"), "cables take an area, not a thickness");
      if (has(s, "axes")) error(s["axes"], sub(p, "axes"), "cables take no axes");
      size = positive(s, "area", p, true, "the cross-section area");
    }
    std::optional<SheetAxes> axes;
    bool axes_ok = true;
    if (membrane && has(s, "axes")) {
      axes = parse_axes(s["axes"], sub(p, "axes"));
      axes_ok = axes.has_value();
    }
    auto integration = shape::Integration::kGauss;
    bool integration_ok = true;
    if (has(s, "integration")) {
      const auto how = text(s, "integration", p, true);
      if (how && *how == "nodal")
        integration = shape::Integration::kNodal;
      else if (how && *how != "gauss") {
        error(s["integration"], sub(p, "integration"),
              fmt::format("unknown integration '{}' (gauss | nodal)", *how));
        integration_ok = false;
      } else if (!how)
        integration_ok = false;
    }
    // The section's additions to its material: wrinkling (membranes) and prestress.
    MaterialDef law = md;
    bool law_ok = true;
    if (has(s, "wrinkling")) {
      const auto w = boolean(s, "wrinkling", p);
      if (w && *w && !membrane) {
        error(s["wrinkling"], sub(p, "wrinkling"),
              "cables carry no compression already; wrinkling is for membranes");
        law_ok = false;
      }
      law.wrinkling = w.value_or(false);
      wrinkles_ = wrinkles_ || law.wrinkling;
      law_ok = law_ok && w.has_value();
    }
    if (has(s, "wrinkling_stiffness")) {
      const std::string kp = sub(p, "wrinkling_stiffness");
      const auto k = number(s["wrinkling_stiffness"], kp);
      if (!k) {
        law_ok = false;
      } else if (!law.wrinkling) {
        error(s["wrinkling_stiffness"], kp, "applies with wrinkling: true only");
        law_ok = false;
      } else if (!(*k > 0 && *k <= 0.1)) {
        error(s["wrinkling_stiffness"], kp,
              fmt::format("{} is not in (0, 0.1]: the share of the sheet's stiffness kept "
                          "where it wrinkles or goes slack",
                          *k));
        law_ok = false;
      } else {
        law.wrinkling_stiffness = *k;
      }
    }
    if (has(s, "prestress")) {
      const Node ps = s["prestress"];
      const std::string pp = sub(p, "prestress");
      if (membrane) {
        const auto v = ps.IsSequence() && ps.size() == 3 ? vec3(ps, pp) : std::nullopt;
        if (!v) {
          if (!(ps.IsSequence() && ps.size() == 3))
            error(ps, pp,
                  "expected [s11, s22, s12]: a 2nd Piola-Kirchhoff stress in the sheet "
                  "axes (force/area)");
          law_ok = false;
        } else {
          law.prestress = *v;
          const double c = 0.5 * ((*v)[0] + (*v)[1]);
          const double r = std::hypot(0.5 * ((*v)[0] - (*v)[1]), (*v)[2]);
          prestresses_.push_back({ps, pp, c - r, c + r, true});
        }
      } else {
        const auto n = number(ps, pp);
        if (!n) {
          law_ok = false;
        } else if (*n < 0 && !md.cable_law.compression) {
          error(ps, pp,
                "a cable's prestress is a tension (an axial force >= 0); only a truss "
                "(compression: true) takes a negative one");
          law_ok = false;
        } else {
          law.cable_prestress = *n;
          prestresses_.push_back({ps, pp, *n, *n, false});
        }
      }
    }
    const auto sliding = parse_sliding_section(s, p, es, md);
    if (!size || !md.ok || !axes_ok || !integration_ok || !law_ok || !mesh_ok_ || !sliding)
      continue;
    build_blocks(*set, es, law, *size, axes ? &*axes : nullptr, integration, s, p, *sliding);
    in_.block_materials.resize(in_.model.blocks.size(), *mat);
  }
}

std::optional<SheetAxes> Reader::parse_axes(const Node& a, const std::string& p) {
  if (!check_map(a, p, {"points"}) || !require(a, "points", p)) return std::nullopt;
  const Node pts = a["points"];
  const std::string pp = sub(p, "points");
  if (!pts.IsSequence() || pts.size() != 3) {
    error(pts, pp, "expected three points [P1, P2, P3] (node ids or [x, y, z])");
    return std::nullopt;
  }
  Vec3 P[3];
  for (size_t i = 0; i < 3; ++i) {
    if (pts[i].IsSequence()) {
      auto v = vec3(pts[i], item(pp, i));
      if (!v) return std::nullopt;
      P[i] = *v;
    } else {
      auto id = integer(pts[i], item(pp, i), "node id or [x, y, z]");
      if (!id) return std::nullopt;
      auto it = in_.model.node_index.find(*id);
      const Vec3* at = nullptr;
      if (it != in_.model.node_index.end()) {
        P[i] = in_.model.X.col(it->second);
        continue;
      }
      if (part_)  // a part read: another part's node, its coordinates given by the split
        for (const auto& [pid, x] : part_->points)
          if (pid == *id) at = &x;
      if (!at) {
        error(pts[i], item(pp, i), fmt::format("undefined node {}", *id));
        return std::nullopt;
      }
      P[i] = *at;
    }
  }
  try {
    return axes_from_points(P[0], P[1], P[2]);
  } catch (const std::invalid_argument& e) {
    error(pts, pp, fmt::format("the points do not define a plane: {}", e.what()));
    return std::nullopt;
  }
}

void Reader::build_blocks(const std::string& set, const ElementSet& es, const MaterialDef& md,
                          double size, const SheetAxes* axes, shape::Integration integration,
                          const Node& at, const std::string& p,
                          const SlidingCableSection& sliding_section) {
  // A panel of a cutting pattern measures strain from its own flat reference.
  const std::optional<NodePositions> panel = panel_reference_of(set, es, at, p);
  const NodePositions& X = panel ? *panel : in_.model.X;
  for (size_t gi = 0; gi < es.groups.size(); ++gi) {
    const ElementGroup& g = es.groups[gi];
    std::vector<int> conn;
    conn.reserve(g.node_ids.size());
    bool ok = true;
    for (long id : g.node_ids) {
      auto it = in_.model.node_index.find(id);
      if (it == in_.model.node_index.end()) {
        error(at, p, fmt::format("set '{}' refers to undefined node {}", set, id));
        ok = false;
        break;
      }
      conn.push_back(it->second);
    }
    if (!ok) continue;
    const bool sliding = g.type == "sliding_cable";
    if (const ShapeProblem bad =
            sliding ? ShapeProblem{} : check_shapes(g.type, conn, X, in_.model.node_ids);
        bad.element >= 0) {
      const std::string where = g.line > 0 ? fmt::format("{}:{}", name_, g.line)
                                           : fmt::format("{}:{}", name_, line_of(at));
      errors_.push_back(
          fmt::format("{}: {}: element {} of set '{}' ({}) is degenerate or "
                      "inverted: it {}",
                      where, g.line > 0 ? "mesh.elements" : p,
                      g.ids[static_cast<size_t>(bad.element)], set, g.type, bad.what));
      continue;
    }
    BlockSetupReport report;
    const int chain_nodes = static_cast<int>(conn.size());  // before conn moves
    std::unique_ptr<ElementBlock> block;
    try {
      if (md.cable && sliding)
        block = make_sliding_cable_block(
            set, chain_nodes, std::move(conn), X,
            CableLaw{md.cable_law.E, md.cable_law.compression, md.cable_prestress / size},
            md.density, size, report, sliding_section);
      else if (md.cable)
        block = make_cable_block(
            g.type, set, std::move(conn), X,
            CableLaw{md.cable_law.E, md.cable_law.compression, md.cable_prestress / size},
            md.density, size, integration, report);
      else
        block = make_membrane_block(g.type, set, std::move(conn), X, md.sheet_law(), md.density,
                                    size, axes, integration, report);
    } catch (const std::exception& e) {
      error(at, p, fmt::format("set '{}': {}", set, e.what()));
      continue;
    }
    const std::string where =
        g.line > 0 ? fmt::format("{}:{}", name_, g.line) : fmt::format("{}:{}", name_, line_of(at));
    if (report.worst_element >= 0 && !(report.worst_jacobian > 0)) {
      const long eid = g.ids[static_cast<size_t>(report.worst_element)];
      errors_.push_back(
          md.cable ? fmt::format("{}: {}: element {} of set '{}' has zero length", where,
                                 g.line > 0 ? "mesh.elements" : p, eid, set)
                   : fmt::format("{}: {}: element {} of set '{}' is degenerate or inverted "
                                 "(reference Jacobian {:.3g} <= 0)",
                                 where, g.line > 0 ? "mesh.elements" : p, eid, set,
                                 report.worst_jacobian));
      continue;
    }
    if (report.poor_axes_element >= 0 && report.poor_axes_quality < 0.5)
      warn(at, p,
           fmt::format("set '{}': the sheet axes project poorly onto element {} (quality "
                       "{:.2f}): the sheet is far from the plane of the axes points",
                       set, g.ids[static_cast<size_t>(report.poor_axes_element)],
                       report.poor_axes_quality));
    set_blocks_[set].push_back(static_cast<int>(in_.model.blocks.size()));
    if (part_) {  // a part read: the block spread to the whole block's numbering
      const auto& [whole, own] = part_groups_.at(set).at(gi);
      block->spread(whole, own);
      std::vector<long> ids(static_cast<size_t>(whole), 0);
      for (size_t k = 0; k < own.size(); ++k) ids[static_cast<size_t>(own[k])] = g.ids[k];
      in_.element_ids.push_back(std::move(ids));
      part_own_.push_back(own);
    } else {
      in_.element_ids.push_back(g.ids);
    }
    in_.model.blocks.push_back(std::move(block));
  }
}

}  // namespace velum::io::model_file
