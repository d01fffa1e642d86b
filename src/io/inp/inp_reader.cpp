// The two ways a deck is read (velum/io/inp_reader.hpp): as a mesh file and as a whole model.

#include "velum/io/inp_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "model.hpp"

namespace velum::io {
namespace inp {

void report_unread(const std::vector<Keyword>& keywords, const std::vector<bool>& used,
                   Diagnostics& diag, const std::string& why) {
  // Output requests and bookkeeping: they change no result.
  static const std::set<std::string> kHarmless = {
      "HEADING",       "NODE PRINT",   "EL PRINT",       "NODE FILE",         "EL FILE",
      "OUTPUT",        "NODE OUTPUT",  "ELEMENT OUTPUT", "ENERGY OUTPUT",     "CONTACT OUTPUT",
      "CONTACT PRINT", "ENERGY PRINT", "SECTION PRINT",  "RESTART",           "MONITOR",
      "PREPRINT",      "FILE FORMAT",  "SUMMARY",        "PHYSICAL CONSTANTS"};
  static const std::map<std::string, std::string> kHints = {
      {"SHELL SECTION", "Velum's sheets are membranes: use M3D elements with *MEMBRANE SECTION"},
      {"BEAM SECTION",
       "Velum's lines are cables and trusses: use T3D elements with *SOLID "
       "SECTION"},
      {"PART",
       "assembly-based decks (*PART, *INSTANCE, *ASSEMBLY) are not supported: write "
       "the flat deck (Abaqus: 'Write input' without parts and assemblies)"},
      {"INSTANCE", "assembly-based decks are not supported: write the flat deck"},
      {"ASSEMBLY", "assembly-based decks are not supported: write the flat deck"},
      {"MASS", "point masses: give them in the YAML model (masses:)"},
      {"EQUATION", "multi-point constraints are not supported"},
      {"CONTROLS", "Velum's Newton controls are analysis.newton in the YAML model"}};
  for (size_t i = 0; i < keywords.size(); ++i) {
    if (used[i]) continue;
    const Keyword& k = keywords[i];
    if (k.name == "INCLUDE") continue;  // read in place
    if (kHarmless.count(k.name)) {
      diag.warn(k, fmt::format("not read ({}); it changes no result", why));
      continue;
    }
    auto hint = kHints.find(k.name);
    diag.error(k, hint != kHints.end()
                      ? fmt::format("not supported: {}", hint->second)
                      : fmt::format("not supported ({}): see docs/inp-import.md for the keywords "
                                    "Velum reads",
                                    why));
  }
}

}  // namespace inp

MeshData read_inp_mesh(const std::filesystem::path& file, std::vector<std::string>& warnings) {
  inp::Diagnostics diag;
  const auto keywords = inp::read_deck(file, diag);
  std::vector<bool> used(keywords.size(), false);
  inp::Mesh mesh = inp::read_mesh(keywords, used, diag);
  // Everything else a mesh file cannot give: one warning per keyword name (the YAML model
  // holds the materials, sections, loads and analysis).
  std::map<std::string, std::pair<int, int>> skipped;  // name -> first (file, line)
  for (size_t i = 0; i < keywords.size(); ++i)
    if (!used[i] && keywords[i].name != "INCLUDE" && keywords[i].name != "HEADING")
      skipped.try_emplace(keywords[i].name, keywords[i].file, keywords[i].line);
  for (const auto& [name, where] : skipped)
    diag.warnings.push_back(
        fmt::format("{}: *{}: not read: a mesh.file gives nodes, elements "
                    "and sets only (velum import reads the whole deck)",
                    diag.where(where.first, where.second), name));
  if (mesh.nodes.empty() && diag.errors.empty())
    diag.errors.push_back(fmt::format("{}: the deck has no *NODE", file.string()));
  if (mesh.elements.empty() && diag.errors.empty())
    diag.errors.push_back(fmt::format("{}: the deck has no *ELEMENT", file.string()));
  if (!diag.errors.empty()) throw InpError(diag.errors);

  MeshData out;
  out.nodes = mesh.nodes;
  // Each element in the first set naming it, in the order of the file.
  std::vector<int> claimed(mesh.elements.size(), -1);
  std::map<std::string, size_t> group_at;  // set|type -> group
  auto put = [&](const std::string& set, size_t e) {
    const inp::Element& el = mesh.elements[e];
    auto [it, fresh] = group_at.try_emplace(set + "|" + el.type, out.groups.size());
    if (fresh) out.groups.push_back({set, el.type, {}, {}, 0});
    ElementGroup& g = out.groups[it->second];
    g.ids.push_back(el.id);
    g.node_ids.insert(g.node_ids.end(), el.nodes.begin(), el.nodes.end());
  };
  for (size_t s = 0; s < mesh.elsets.size(); ++s) {
    const inp::Set& set = mesh.elsets[s];
    size_t taken = 0;
    std::string other;
    for (long id : set.ids) {
      const size_t e = mesh.element_at.at(id);
      if (claimed[e] >= 0) {
        if (other.empty()) other = mesh.elsets[static_cast<size_t>(claimed[e])].name;
        continue;
      }
      claimed[e] = static_cast<int>(s);
      put(set.name, e);
      ++taken;
    }
    if (taken < set.ids.size())
      diag.warnings.push_back(fmt::format(
          "{}: element set '{}': {} of its {} elements are in set '{}'{} already (Velum keeps "
          "each element in one set, the first naming it): '{}' {}",
          diag.where(set.file, set.line), set.name, set.ids.size() - taken, set.ids.size(), other,
          set.ids.size() - taken > 1 ? " or others" : "", set.name,
          taken == 0 ? "is a node set only" : "holds the others"));
  }
  for (long id : mesh.unnamed_elements)
    if (const size_t e = mesh.element_at.at(id); claimed[e] < 0) put("all", e);
  for (const auto& s : mesh.nsets) out.node_sets[s.name] = s.ids;
  for (const auto& s : mesh.elsets) {
    std::set<long> nodes;
    for (long id : s.ids)
      for (long n : mesh.elements[mesh.element_at.at(id)].nodes) nodes.insert(n);
    if (!out.node_sets.count(s.name)) out.node_sets[s.name].assign(nodes.begin(), nodes.end());
  }
  warnings.insert(warnings.end(), diag.warnings.begin(), diag.warnings.end());
  return out;
}

std::string import_inp(const std::filesystem::path& file, std::vector<std::string>& warnings) {
  inp::Diagnostics diag;
  const auto keywords = inp::read_deck(file, diag);
  std::vector<bool> used(keywords.size(), false);
  inp::Mesh mesh = inp::read_mesh(keywords, used, diag);
  inp::Properties props = inp::read_properties(keywords, used, diag);
  const std::vector<inp::Step> steps = inp::read_step(keywords, mesh, used, diag);
  std::string title;
  for (size_t i = 0; i < keywords.size(); ++i)
    if (keywords[i].name == "HEADING") {
      used[i] = true;
      if (!keywords[i].data.empty()) {
        const auto& f = keywords[i].data[0].fields;
        for (size_t j = 0; j < f.size(); ++j) {
          if (j) title += ", ";
          title += f[j];
        }
      }
    }
  inp::report_unread(keywords, used, diag, "velum import");
  if (mesh.nodes.empty() && diag.errors.empty())
    diag.errors.push_back(fmt::format("{}: the deck has no *NODE", file.string()));
  if (mesh.elements.empty() && diag.errors.empty())
    diag.errors.push_back(fmt::format("{}: the deck has no *ELEMENT", file.string()));
  std::string yaml;
  if (diag.errors.empty()) yaml = inp::write_yaml(title, mesh, props, steps, diag);
  warnings.insert(warnings.end(), diag.warnings.begin(), diag.warnings.end());
  if (!diag.errors.empty()) throw InpError(diag.errors);
  return yaml;
}

}  // namespace velum::io
