#include "velum/io/form_model.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "velum/io/results_writer.hpp"

namespace velum::io {

YAML::Node position_row(long id, const Vec3& p) {
  YAML::Node row(YAML::NodeType::Sequence);
  row.SetStyle(YAML::EmitterStyle::Flow);
  row.push_back(id);
  // Plain numbers: fmt's shortest round-trip form, read back to the same double.
  for (int c = 0; c < 3; ++c) row.push_back(fmt::format("{:.17g}", p[c]));
  return row;
}

YAML::Node model_at_shape(const ModelInput& input, const NodePositions& x,
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
    // Relative to the written file's folder (a results folder moved with its model and mesh
    // still finds it); absolute only where no relative path leads there.
    namespace fs = std::filesystem;
    fs::path p = mesh["file"].as<std::string>();
    if (p.is_relative()) p = fs::absolute(input.base_dir / p);
    std::error_code ec;
    const fs::path rel = fs::relative(p, fs::absolute(file).parent_path(), ec);
    mesh["file"] = (ec || rel.empty() ? p.lexically_normal() : rel).generic_string();
  }
  YAML::Node positions(YAML::NodeType::Sequence);
  for (int n = 0; n < x.cols(); ++n)
    positions.push_back(position_row(input.model.node_ids[static_cast<size_t>(n)], x.col(n)));
  mesh["positions"] = positions;
  YAML::Node analysis = root["analysis"];
  analysis["type"] = "static";
  analysis.remove("form_finding");
  if (root["output"] && root["output"].IsMap()) root["output"].remove("directory");
  return root;
}

void write_model_yaml(const YAML::Node& root, const std::string& comment,
                      const std::filesystem::path& file) {
  YAML::Emitter out;
  out << YAML::Comment(comment);
  out << YAML::Newline << root;
  write_file_atomically(file, std::string(out.c_str()) + "\n");
}

void write_form_model(const ModelInput& input, const NodePositions& x,
                      const std::filesystem::path& file) {
  write_model_yaml(model_at_shape(input, x, file),
                   fmt::format("Written by velum form finding from {}: the found shape "
                               "(mesh.positions), the prestress carried over; run as the next "
                               "analysis",
                               input.file.filename().string()),
                   file);
}

}  // namespace velum::io
