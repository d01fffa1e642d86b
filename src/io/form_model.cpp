#include "velum/io/form_model.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "velum/io/results_writer.hpp"

namespace velum::io {

void write_form_model(const ModelInput& input, const NodePositions& x,
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
    // Relative to form.yaml's folder (a results folder moved with its model and mesh still
    // finds it); absolute only where no relative path leads there.
    namespace fs = std::filesystem;
    fs::path p = mesh["file"].as<std::string>();
    if (p.is_relative()) p = fs::absolute(input.base_dir / p);
    std::error_code ec;
    const fs::path rel = fs::relative(p, fs::absolute(file).parent_path(), ec);
    mesh["file"] = (ec || rel.empty() ? p.lexically_normal() : rel).generic_string();
  }
  YAML::Node positions(YAML::NodeType::Sequence);
  for (int n = 0; n < x.cols(); ++n) {
    YAML::Node row(YAML::NodeType::Sequence);
    row.SetStyle(YAML::EmitterStyle::Flow);
    row.push_back(input.model.node_ids[n]);
    for (int c = 0; c < 3; ++c) row.push_back(fmt::format("{:.17g}", x(c, n)));
    positions.push_back(row);
  }
  mesh["positions"] = positions;
  YAML::Node analysis = root["analysis"];
  analysis["type"] = "static";
  analysis.remove("form_finding");
  if (root["output"] && root["output"].IsMap()) root["output"].remove("directory");
  // Emitted as plain numbers: fmt's shortest round-trip form, read back to the same double.
  YAML::Emitter out;
  out << YAML::Comment(fmt::format(
      "Written by velum form finding from {}: the found shape (mesh.positions), the prestress "
      "carried over; run as the next analysis",
      input.file.filename().string()));
  out << YAML::Newline << root;
  write_file_atomically(file, std::string(out.c_str()) + "\n");
}

}  // namespace velum::io
