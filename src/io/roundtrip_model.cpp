#include "velum/io/roundtrip_model.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <set>

#include "velum/io/form_model.hpp"

namespace velum::io {

void write_roundtrip_model(const ModelInput& input, const NodePositions& x,
                           const std::vector<PatternPanel>& panels, double warp, double fill,
                           const std::filesystem::path& file) {
  YAML::Node root = model_at_shape(input, x, file);
  YAML::Node mesh = root["mesh"];
  mesh.remove("reference_positions");
  YAML::Node refs(YAML::NodeType::Sequence);
  std::set<std::string> names;
  for (const auto& p : panels) {
    YAML::Node panel;
    panel["elements"] = p.name;
    YAML::Node ps(YAML::NodeType::Sequence);
    for (size_t k = 0; k < p.flat.nodes.size(); ++k) {
      const Vec2& q = p.flat.uv[k];
      ps.push_back(position_row(p.node_ids[k], Vec3(q.x() * (1 - warp), q.y() * (1 - fill), 0)));
    }
    panel["positions"] = ps;
    refs.push_back(panel);
    names.insert(p.name);
  }
  mesh["panel_references"] = refs;
  // The prestress is what the sewn panels must reach by their strain; the flat panel's warp
  // runs along u, which is global x on the flat reference.
  for (YAML::Node s : root["sections"])
    if (s.IsMap() && s["elements"] && names.count(s["elements"].as<std::string>())) {
      s.remove("prestress");
      s.remove("axes");
    }
  root.remove("steps");
  root.remove("patterns");
  write_model_yaml(root,
                   fmt::format("Written by velum pattern from {}: the compensated flat panels "
                               "(mesh.panel_references) sewn onto the shape, their sections "
                               "without prestress; run it to see the stress the panels reach "
                               "against the designed prestress",
                               input.file.filename().string()),
                   file);
}

}  // namespace velum::io
