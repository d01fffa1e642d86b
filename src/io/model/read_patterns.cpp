// Reads patterns: (the panels `velum pattern` flattens and their compensation).

#include <fmt/format.h>

#include <cmath>
#include <map>

#include <algorithm>

#include "reader.hpp"
#include "velum/analysis/flatten.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io::model_file {

namespace {
// Beyond this a compensation is a typing error (a percentage given as one) rather than a
// fabric's prestress strain, which stays within a few percent.
constexpr double kMaxCompensation = 0.1;
}  // namespace

void Reader::parse_patterns(const Node& pn) {
  if (!check_map(
          pn, "patterns",
          {"panels", "compensation", "seam_allowance", "seams", "seam_tolerance", "seam_snap"}))
    return;
  PatternSettings& out = in_.patterns;
  if (has(pn, "seams")) parse_seams(pn);
  out.panels_where = has(pn, "panels")
                         ? fmt::format("{}:{}: patterns.panels", name_, line_of(pn["panels"]))
                         : fmt::format("{}:{}: patterns", name_, line_of(pn));
  if (!out.seams.empty()) {
    // The panels the seams cut: names for them, not sets yet.
    if (has(pn, "panels")) {
      const Node ps = pn["panels"];
      if (!ps.IsSequence() || ps.size() == 0) {
        error(ps, "patterns.panels", "expected a list of names for the panels the seams cut");
      } else {
        for (size_t i = 0; i < ps.size(); ++i) {
          if (!ps[i].IsScalar()) {
            error(ps[i], item("patterns.panels", i), "expected a name");
            continue;
          }
          const std::string name = ps[i].Scalar();
          if (std::find(out.panels.begin(), out.panels.end(), name) != out.panels.end())
            error(ps[i], item("patterns.panels", i), fmt::format("'{}' is named twice", name));
          out.panels.push_back(name);
        }
      }
    }
  } else if (require(pn, "panels", "patterns")) {
    const Node ps = pn["panels"];
    if (!ps.IsSequence() || ps.size() == 0) {
      error(ps, "patterns.panels", "expected a list of element set names");
    } else {
      // an element's sorted node ids -> the panel and element that have it
      std::map<std::vector<long>, std::pair<std::string, long>> owner;
      for (size_t i = 0; i < ps.size(); ++i) {
        const std::string p = item("patterns.panels", i);
        if (!ps[i].IsScalar()) {
          error(ps[i], p, "expected an element set name");
          continue;
        }
        const std::string name = ps[i].Scalar();
        auto it = element_sets_.find(name);
        if (it == element_sets_.end()) {
          error(ps[i], p,
                fmt::format("undefined element set '{}'{}", name,
                            suggestion(name, keys_of(element_sets_))));
          continue;
        }
        if (it->second.dimension != 2) {
          error(ps[i], p, fmt::format("element set '{}' is not a surface: a panel is one", name));
          continue;
        }
        // The same element (by id, or by its nodes) in two panels.
        bool overlaps = false;
        for (const auto& g : it->second.groups) {
          const shape::ShapeInfo* shape = shape::find(g.type);
          const size_t nn = shape ? static_cast<size_t>(shape->nodes) : 1;
          for (size_t e = 0; e < g.ids.size() && !overlaps; ++e) {
            std::vector<long> key(g.node_ids.begin() + static_cast<long>(e * nn),
                                  g.node_ids.begin() + static_cast<long>((e + 1) * nn));
            std::sort(key.begin(), key.end());
            auto [o, added] = owner.emplace(key, std::make_pair(name, g.ids[e]));
            if (!added && o->second.first != name) {
              error(ps[i], p,
                    fmt::format("panel '{}' overlaps panel '{}' (element {} lies on element {}): "
                                "panels must not share elements",
                                name, o->second.first, g.ids[e], o->second.second));
              overlaps = true;
            }
          }
        }
        // A panel is flattened as one disc (corner triangles; quadrilaterals split).
        PanelMesh mesh;
        for (const auto& g : it->second.groups) {
          const shape::ShapeInfo* shape = shape::find(g.type);
          if (!shape || !shape->surface()) continue;
          const auto nn = static_cast<size_t>(shape->nodes);
          for (size_t e = 0; e * nn < g.node_ids.size(); ++e) {
            int c[4] = {0, 0, 0, 0};
            bool known = true;
            for (int k = 0; k < std::min(shape->corners, 4); ++k) {
              auto at = in_.model.node_index.find(g.node_ids[e * nn + static_cast<size_t>(k)]);
              known = known && at != in_.model.node_index.end();
              if (known) c[k] = at->second;
            }
            if (!known) continue;  // reported with the element
            mesh.triangles.push_back({c[0], c[1], c[2]});
            if (shape->corners == 4) mesh.triangles.push_back({c[0], c[2], c[3]});
          }
        }
        if (std::string why = disc_problem(mesh, in_.model.num_nodes()); !why.empty())
          error(ps[i], p, fmt::format("panel '{}' cannot be flattened: {}", name, why));
        out.panels.push_back(name);
      }
    }
  }
  if (auto t = non_negative(pn, "seam_tolerance", "patterns", "a distance"))
    out.seam_tolerance = *t;
  if (auto f = non_negative(pn, "seam_snap", "patterns", "a fraction of an edge")) {
    if (*f >= 0.5)
      error(pn["seam_snap"], "patterns.seam_snap",
            fmt::format("{:g} is not below 0.5: a crossing snaps to the nearer corner of its edge",
                        *f));
    else
      out.seam_snap = *f;
  }
  if (auto a = non_negative(pn, "seam_allowance", "patterns", "a seam allowance"))
    out.seam_allowance = *a;
  if (has(pn, "compensation")) {
    const Node c = pn["compensation"];
    const std::string p = "patterns.compensation";
    if (!c.IsSequence() || c.size() != 2) {
      error(c, p, "expected [warp, fill]: the strains the flat panels are shrunk by");
      return;
    }
    auto w = number(c[0], p), f = number(c[1], p);
    if (!w || !f) return;
    for (double v : {*w, *f})
      if (!(std::abs(v) <= kMaxCompensation)) {
        error(c, p,
              fmt::format("a compensation of {:g} is outside the plausible range [-{:g}, {:g}] "
                          "(strains, not percent: 0.01 is 1%)",
                          v, kMaxCompensation, kMaxCompensation));
        return;
      }
    out.warp = *w, out.fill = *f;
  }
}

}  // namespace velum::io::model_file

namespace velum::io::model_file {

void Reader::parse_seams(const Node& pn) {
  const Node ss = pn["seams"];
  if (!ss.IsSequence() || ss.size() == 0) {
    error(ss, "patterns.seams",
          "expected a list of seams: {points: [A, B, ...]} (geodesics through points, each "
          "[x, y, z] or a node id) or {nodes: [id, ...]} (along element edges)");
    return;
  }
  for (size_t i = 0; i < ss.size(); ++i) {
    const std::string p = item("patterns.seams", i);
    const Node s = ss[i];
    if (!check_map(s, p, {"points", "nodes"})) continue;
    const bool path = has(s, "nodes");
    if (path == has(s, "points")) {
      error(s, p, "give either points: (a geodesic) or nodes: (a node path)");
      continue;
    }
    const char* key = path ? "nodes" : "points";
    const Node list = s[key];
    const std::string lp = sub(p, key);
    if (!list.IsSequence() || list.size() < 2) {
      error(list, lp,
            path ? "expected two or more node ids along element edges"
                 : "expected two or more points, each [x, y, z] or a node id");
      continue;
    }
    PatternSettings::Seam seam;
    seam.where = fmt::format("{}:{}: {}", name_, line_of(s), p);
    seam.path = path;
    bool ok = true;
    for (size_t k = 0; k < list.size() && ok; ++k) {
      const Node v = list[k];
      const std::string q = item(lp, k);
      if (v.IsSequence() && !path) {
        auto x = vec3(v, q);
        ok = x.has_value();
        if (ok) seam.nodes.push_back(-1), seam.points.push_back(*x);
        continue;
      }
      auto id = integer(v, q, "node id");
      ok = id.has_value();
      if (!ok) continue;
      auto it = in_.model.node_index.find(*id);
      if (it == in_.model.node_index.end()) {
        error(v, q, fmt::format("undefined node {}", *id));
        ok = false;
        continue;
      }
      seam.nodes.push_back(it->second);
      seam.points.push_back(in_.model.X.col(it->second));
    }
    if (ok) in_.patterns.seams.push_back(std::move(seam));
  }
}

}  // namespace velum::io::model_file
