#include "velum/io/roundtrip_model.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <set>

#include "velum/io/results_writer.hpp"

namespace velum::io {
namespace {

YAML::Node row(long id, const Vec3& p) {
  YAML::Node r(YAML::NodeType::Sequence);
  r.SetStyle(YAML::EmitterStyle::Flow);
  r.push_back(id);
  for (int c = 0; c < 3; ++c) r.push_back(fmt::format("{:.17g}", p[c]));
  return r;
}

}  // namespace

void write_roundtrip_model(const ModelInput& input, const NodePositions& x,
                           const std::vector<PatternPanel>& panels, double warp, double fill,
                           const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::Load(input.yaml);
  } catch (const YAML::Exception& e) {
    throw OutputError(
        fmt::format("{}: cannot write it: the model's YAML: {}", file.string(), e.what()));
  }
  YAML::Node mesh = root["mesh"];
  if (mesh["file"]) {
    namespace fs = std::filesystem;
    fs::path p = mesh["file"].as<std::string>();
    if (p.is_relative()) p = fs::absolute(input.base_dir / p);
    std::error_code ec;
    const fs::path rel = fs::relative(p, fs::absolute(file).parent_path(), ec);
    mesh["file"] = (ec || rel.empty() ? p.lexically_normal() : rel).generic_string();
  }
  YAML::Node positions(YAML::NodeType::Sequence);
  for (int n = 0; n < x.cols(); ++n) positions.push_back(row(input.model.node_ids[n], x.col(n)));
  mesh["positions"] = positions;
  mesh.remove("reference_positions");
  YAML::Node refs(YAML::NodeType::Sequence);
  std::set<std::string> names;
  for (const auto& p : panels) {
    YAML::Node panel;
    panel["elements"] = p.name;
    YAML::Node ps(YAML::NodeType::Sequence);
    for (size_t k = 0; k < p.flat.nodes.size(); ++k) {
      const Vec2& q = p.flat.uv[k];
      ps.push_back(row(p.node_ids[k], Vec3(q.x() * (1 - warp), q.y() * (1 - fill), 0)));
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
  YAML::Node analysis = root["analysis"];
  analysis["type"] = "static";
  analysis.remove("form_finding");
  root.remove("steps");
  root.remove("patterns");
  if (root["output"] && root["output"].IsMap()) root["output"].remove("directory");
  YAML::Emitter out;
  out << YAML::Comment(fmt::format(
      "Written by velum pattern from {}: the compensated flat panels (mesh.panel_references) "
      "sewn onto the shape, their sections without prestress; run it to see the stress the "
      "panels reach against the designed prestress",
      input.file.filename().string()));
  out << YAML::Newline << root;
  write_file_atomically(file, std::string(out.c_str()) + "\n");
}

}  // namespace velum::io
