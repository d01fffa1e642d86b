// The model file `velum seams` writes (include/velum/io/cut_model.hpp).
#include "velum/io/cut_model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include "velum/io/results_writer.hpp"

namespace velum::io {
namespace {

// A list of set names with each cut set replaced by its panels.
YAML::Node expanded_sets(const YAML::Node& list,
                         const std::map<std::string, std::vector<std::string>>& renamed) {
  YAML::Node sets(YAML::NodeType::Sequence);
  sets.SetStyle(YAML::EmitterStyle::Flow);
  for (const auto& s : list) {
    auto it = s.IsScalar() ? renamed.find(s.as<std::string>()) : renamed.end();
    if (it == renamed.end()) {
      sets.push_back(s);
    } else {
      for (const auto& panel : it->second) sets.push_back(panel);
    }
  }
  return sets;
}

// A list of entries (sections, loads, contact): each naming a cut set under `elements` is
// repeated for each of its panels; lists of sets (`elements`, `surfaces`) get the panels.
YAML::Node expand_entries(const YAML::Node& list,
                          const std::map<std::string, std::vector<std::string>>& renamed) {
  YAML::Node out(YAML::NodeType::Sequence);
  for (const auto& entry : list) {
    YAML::Node e = YAML::Clone(entry);
    if (e.IsMap() && e["elements"] && e["elements"].IsScalar()) {
      if (auto it = renamed.find(e["elements"].as<std::string>()); it != renamed.end()) {
        for (const auto& panel : it->second) {
          YAML::Node copy = YAML::Clone(e);
          copy["elements"] = panel;
          out.push_back(copy);
        }
        continue;
      }
    }
    if (e.IsMap())
      for (const char* key : {"elements", "surfaces"})
        if (e[key] && e[key].IsSequence()) e[key] = expanded_sets(e[key], renamed);
    out.push_back(e);
  }
  return out;
}

}  // namespace

void write_cut_model(const ModelInput& input, const CutMesh& mesh,
                     const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::Load(input.yaml);
  } catch (const YAML::Exception& e) {
    throw OutputError(
        fmt::format("{}: cannot write it: the model's YAML: {}", file.string(), e.what()));
  }
  root.remove("mesh");
  for (const char* key : {"sections", "loads", "contact"}) {
    if (root[key] && root[key].IsSequence()) root[key] = expand_entries(root[key], mesh.renamed);
  }
  if (root["patterns"] && root["patterns"].IsMap()) {
    YAML::Node p = root["patterns"];
    p.remove("seams");
    p.remove("seam_tolerance");
    p.remove("seam_snap");
    YAML::Node panels(YAML::NodeType::Sequence);
    panels.SetStyle(YAML::EmitterStyle::Flow);
    for (const auto& name : mesh.panels) panels.push_back(name);
    p["panels"] = panels;
  }
  if (root["output"] && root["output"].IsMap()) root["output"].remove("directory");
  YAML::Emitter out;
  out << YAML::Comment(fmt::format(
      "Written by velum seams from {}: the shape cut into panels along the seams (mesh at the "
      "shape; sections and loads of a cut set given per panel)",
      input.file.filename().string()));
  out << YAML::Newline << root;
  // The mesh by hand: one line per node and per element set (large meshes are written fast).
  fmt::memory_buffer m;
  fmt::format_to(std::back_inserter(m), "mesh:\n  nodes:\n");
  for (long n = 0; n < mesh.x.cols(); ++n)
    fmt::format_to(std::back_inserter(m), "    - [{}, {:.17g}, {:.17g}, {:.17g}]\n",
                   mesh.node_ids[static_cast<size_t>(n)], mesh.x(0, n), mesh.x(1, n), mesh.x(2, n));
  fmt::format_to(std::back_inserter(m), "  elements:\n");
  for (const auto& [name, elements] : mesh.sets) {
    // One entry per element type of the set.
    std::map<std::string, std::vector<const CutMesh::Element*>> by_type;
    for (const auto& e : elements) by_type[e.type].push_back(&e);
    for (const auto& [type, list] : by_type) {
      fmt::format_to(std::back_inserter(m), "    - {{set: {}, type: {}, ids: [", name, type);
      for (size_t k = 0; k < list.size(); ++k)
        fmt::format_to(std::back_inserter(m), "{}{}", k ? ", " : "", list[k]->id);
      fmt::format_to(std::back_inserter(m), "],\n       connectivity: [");
      for (size_t k = 0; k < list.size(); ++k)
        fmt::format_to(std::back_inserter(m), "{}[{}]", k ? ", " : "",
                       fmt::join(list[k]->nodes, ", "));
      fmt::format_to(std::back_inserter(m), "]}}\n");
    }
  }
  if (!mesh.node_sets.empty()) {
    fmt::format_to(std::back_inserter(m), "  node_sets:\n");
    for (const auto& [name, ids] : mesh.node_sets)
      fmt::format_to(std::back_inserter(m), "    {}: [{}]\n", name, fmt::join(ids, ", "));
  }
  write_file_atomically(file, std::string(out.c_str()) + "\n" + fmt::to_string(m));
}

}  // namespace velum::io
