// The model as a whole (from a file, YAML text or an in-memory YAML node): loading the YAML, the
// order in which its sections are read, and the checks that need all of them. Each section is read
// in model/read_*.cpp.
#include "velum/io/model_reader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string_view>
#include <utility>

#include "model/reader.hpp"
#include "model/restart_fingerprint.hpp"
#include "model/yaml_structure.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/io/model_reader_yaml.hpp"

namespace velum::io {

InputError::InputError(std::vector<std::string> messages)
    : std::runtime_error(messages.empty() ? std::string("bad input") : messages.front()),
      messages_(std::move(messages)) {}

int edit_distance(std::string_view a, std::string_view b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] =
          std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1] ? 1 : 0)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

namespace model_file {
namespace {

/// The 1-based lines where the first and the second YAML document of `text` begin (0: none).
/// YAML forbids a document marker ("---" or "..." at the start of a line, then a blank or the
/// end of the line) inside any content, so markers are found line by line.
std::pair<int, int> document_lines(std::string_view text) {
  int line = 0, first = 0;
  bool ended = false;  // "..." closed the first document
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    auto marker = [&](std::string_view m) {
      return l.substr(0, 3) == m && (l.size() == 3 || l[3] == ' ' || l[3] == '\t' || l[3] == '\r');
    };
    if (marker("---")) {
      if (first > 0) return {first, line};
      first = line;
      continue;
    }
    if (marker("...")) {
      ended = first > 0;
      continue;
    }
    const size_t c = l.find_first_not_of(" \t\r");
    if (c == std::string_view::npos || l[c] == '#') continue;
    if (first == 0 && l[0] == '%') continue;  // a directive
    if (ended) return {first, line};
    if (first == 0) first = line;
  }
  return {first, 0};
}

/// The model file's text, refused before it is read if it is not a regular file (a FIFO would
/// block, a device never end) or larger than kMaxModelFileBytes.
std::string model_file_text(const std::filesystem::path& file, const std::string& name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (fs::is_directory(st))
    throw InputError({fmt::format("{}: is a directory, not a model file", name)});
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(
        {fmt::format("{}: not a regular file (a model file is a YAML text file)", name)});
  if (fs::is_regular_file(st)) {
    const auto bytes = fs::file_size(file, ec);
    if (!ec && bytes > kMaxModelFileBytes)
      throw InputError({fmt::format(
          "{}: the model file has {} bytes, more than the limit of {} MiB (put large meshes "
          "in a Gmsh file: mesh.file)",
          name, bytes, kMaxModelFileBytes >> 20)});
  }
  // yaml-cpp 0.7's LoadAll loops forever on some inputs (a flow mapping followed by a comma,
  // found by fuzzing): the file is read whole, its document markers are found in
  // parse_model_text, and only the first document is parsed.
  std::string text;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError({fmt::format("{}: cannot open the model file", name)});
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return text;
}

/// The YAML tree of a model's text: one document only.
YAML::Node parse_model_text(const std::string& yaml, const std::string& name) {
  if (auto [first, second] = document_lines(yaml); second > 0)
    throw InputError({fmt::format(
        "{}:{}: a second YAML document (after '---' or '...'): a model file holds one, which "
        "began at line {}",
        name, second, first)});
  try {
    return YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw InputError({fmt::format("{}:{}: YAML syntax error: {}", name, e.mark.line + 1, e.msg)});
  }
}

}  // namespace

ModelInput Reader::read_file(const std::filesystem::path& file) {
  in_.file = file;
  return read_text(model_file_text(file, name_));
}

ModelInput Reader::read_text(const std::string& yaml) {
  const Node root = parse_model_text(yaml, name_);
  ModelInput in = read(root);
  in.yaml = yaml;
  return in;
}

ModelInput Reader::read(const Node& root) {
  if (!root.IsMap()) {
    throw InputError(
        {fmt::format("{}:{}: the model file must be a mapping of sections (mesh, "
                     "materials, sections, ...)",
                     name_, root.Mark().line + 1 > 0 ? root.Mark().line + 1 : 1)});
  }
  if (auto problems = yaml_structure_problems(root, name_); !problems.empty())
    throw InputError(std::move(problems));
  ModelInput in = has(root, "steps") ? read_steps(root)  // model/read_steps.cpp
                                     : read_one(root);
  in.restart_yaml = restart_fingerprint(root, in.model);
  return in;
}

ModelInput Reader::read_one(const Node& root) {
  try {
    parse(root);
  } catch (const YAML::Exception& e) {
    error_at(e.mark.line, "", fmt::format("malformed entry: {}", e.msg));
  }
  if (!errors_.empty()) throw InputError(errors_);
  in_.base_dir = base_dir_;
  in_.materials_yaml = YAML::Dump(root["materials"]) + "\n" + YAML::Dump(root["sections"]);
  if (in_.analysis.type == AnalysisSettings::Type::kFormFinding) in_.yaml = YAML::Dump(root);
  return std::move(in_);
}

void Reader::parse(const Node& root) {
  check_map(root, "",
            {"title", "mesh", "materials", "sections", "masses", "boundary", "loads", "functions",
             "analysis", "output", "steps", "rigid_bodies", "contact", "patterns"});
  if (auto t = text(root, "title", "", false)) in_.title = *t;
  parse_functions(root["functions"]);
  if (require(root, "mesh", "")) parse_mesh(root["mesh"]);
  if (part_)  // what a part read does not know yet (each needs the whole mesh at set-up)
    for (const char* key : {"rigid_bodies", "contact", "patterns"})
      if (has(root, key))
        error(root[key], key,
              fmt::format("{} is not read with mesh.parts yet: run the model with its whole "
                          "mesh (mesh.file)",
                          key));
  if (require(root, "materials", "")) parse_materials(root["materials"]);
  if (require(root, "sections", "")) parse_sections(root["sections"]);
  if (has(root, "patterns")) parse_patterns(root["patterns"]);
  if (has(root, "masses")) parse_masses(root["masses"]);
  if (has(root, "boundary")) parse_boundary(root["boundary"]);
  if (has(root, "loads")) parse_loads(root["loads"]);
  if (has(root, "rigid_bodies")) parse_rigid_bodies(root["rigid_bodies"]);
  if (has(root, "contact")) parse_contact(root["contact"]);
  if (require(root, "analysis", "")) parse_analysis(root["analysis"]);
  // A contact's multipliers carry the last step's force to the next: in a dynamic analysis a
  // node leaving the body would still be pushed (energy made), so there they are off unless
  // asked for.
  check_free_bodies();
  if (!in_.analysis.equilibrium())
    for (auto& load : in_.model.loads)
      if (auto* c = dynamic_cast<ContactLoad*>(load.get());
          c && !contact_augmented_.count(c->index))
        c->augmented = false;
  parse_output(root["output"], root);
  check_gas_flow();
  final_checks(root);
}

// Form finding seeks the shape in equilibrium with a tension: without one (no prestress, or
// only zeros) there is nothing to find, and a membrane compressed in some direction has no
// such shape (a soap film cannot push). Bad input, not a failed solve.
void Reader::check_form_prestress(const Node& root) {
  const bool tension = std::any_of(prestresses_.begin(), prestresses_.end(),
                                   [](const PrestressSite& s) { return s.greatest > 0; });
  if (!tension)
    error(root["sections"] ? root["sections"] : root, "sections",
          prestresses_.empty()
              ? "analysis.type form_finding needs a prestress: give membrane sections a "
                "'prestress: [s11, s22, s12]' or cable sections a 'prestress' (a tension)"
              : "analysis.type form_finding needs a tension: every section's prestress is zero "
                "or compressive");
  for (const auto& s : prestresses_)
    if (s.membrane && s.least < 0)
      error(s.at, s.path,
            fmt::format("form finding needs a membrane prestress in tension in every direction; "
                        "its principal values are {:.6g} and {:.6g} (a compressed membrane has "
                        "no equilibrium shape)",
                        s.greatest, s.least));
}

void Reader::final_checks(const Node& root) {
  for (const auto& [name, set] : element_sets_) {
    if (set.has_section) continue;
    if (set.from_file && set.dimension == 1) continue;  // a boundary curve: a node set only
    if (mesh_ok_)
      error(root["sections"] ? root["sections"] : root, "sections",
            fmt::format("element set '{}' has no section (material and {})", name,
                        set.dimension == 2 ? "thickness" : "area"));
  }
  if (in_.analysis.type == AnalysisSettings::Type::kFormFinding) check_form_prestress(root);
  if (!errors_.empty()) return;
  if (in_.model.blocks.empty()) {
    error(root, "mesh", "the model has no elements");
    return;
  }
  if (part_) {  // a part read: what only the whole mesh knows, from the split
    finish_part();
    set_up_loads();
    return;
  }
  set_up_loads();  // edge loads' boundary, gas chambers' closure and volume
  std::vector<char> used(static_cast<size_t>(in_.model.num_nodes()), 0);
  for (const auto& b : in_.model.blocks)
    for (int n : b->connectivity()) used[static_cast<size_t>(n)] = 1;
  for (const auto& [name, f] : free_bodies_) used[static_cast<size_t>(f.node)] = 1;  // a body
  int unused = 0;
  long first = 0;
  for (size_t n = 0; n < used.size(); ++n)
    if (!used[n]) {
      if (unused++ == 0) first = in_.model.node_ids[n];
    }
  if (unused > 0) {
    warn(root["mesh"], "mesh",
         fmt::format("{} node(s) belong to no element (first: node {}); they are fixed", unused,
                     first));
    FixedDofs f;
    f.fix = {true, true, true};
    for (size_t n = 0; n < used.size(); ++n)
      if (!used[n]) f.nodes.push_back(static_cast<int>(n));
    in_.model.fixed.push_back(std::move(f));
  }
  // Every component held: a model whose motion is all prescribed still has its answer (the
  // reactions along the motion: Kratos' displacement-controlled truss), and a rigid vessel
  // (every wall held) still has its gas state to march in time; one that nothing moves has none.
  const bool moves =
      std::any_of(in_.model.prescribed.begin(), in_.model.prescribed.end(),
                  [](const PrescribedMotion& p) { return !p.displacement.isZero(); });
  const bool gas_flow = std::any_of(in_.model.gases.begin(), in_.model.gases.end(),
                                    [](const GasLoad& g) { return g.flows(); });
  if (DofMap(in_.model).num_equations() == 0 && !moves && !gas_flow)
    error(root["boundary"] ? root["boundary"] : root, "boundary",
          "every degree of freedom is fixed: there is nothing to solve (0 equations, no "
          "prescribed motion)");
}

}  // namespace model_file

ModelInput read_model(const std::filesystem::path& file) {
  try {
    return model_file::Reader(file.string(), file.parent_path()).read_file(file);
  } catch (const std::bad_alloc&) {
    throw InputError({fmt::format(
        "{}: out of memory while reading the model (or its mesh file): the model is too large "
        "for this machine",
        file.string())});
  }
}

ModelInput read_model_text(const std::string& yaml, const ModelSource& source) {
  return model_file::Reader(source.name, source.base_dir).read_text(yaml);
}

YAML::Node load_model_yaml(const std::filesystem::path& file) {
  const std::string name = file.string();
  YAML::Node root = model_file::parse_model_text(model_file::model_file_text(file, name), name);
  if (auto problems = model_file::yaml_structure_problems(root, name); !problems.empty())
    throw InputError(std::move(problems));
  return root;
}

ModelInput read_model(const YAML::Node& root, const ModelSource& source) {
  return model_file::Reader(source.name, source.base_dir).read(root);
}

}  // namespace velum::io
