// Reads Gmsh .msh files (MSH 2.2 and 4.1, ASCII and binary) with Velum's own parser. It
// replaced the Gmsh library (libgmsh 4.8) as the reader when fuzzing showed what the library
// does with a corrupt file: it sizes arrays from the file's counts unchecked (one flipped byte
// in a binary file asked for 4 TB and, under ASan, aborted the process), leaks on malformed
// MSH 2 files, silently drops elements when a section's count disagrees with its list, and
// reads 5 to 7 files a second (its initialisation). Here no array is sized from a count before
// the bytes it needs are known to be in the file, and every failure names the file and the line
// (ASCII) or byte (binary). The library stays the test suite's oracle (gmsh_reader_test.cpp
// reads the same meshes through both).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <new>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_set>

#include "msh_input.hpp"
#include "velum/io/mesh_data.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum::io {

std::string type_of_gmsh(int gmsh_type) {
  const shape::ShapeInfo* s = shape::find_gmsh(gmsh_type);
  return s ? std::string(s->name) : std::string();
}

namespace {

using msh::Input;
using msh::MshContents;

// A section's count against its lines, before parsing (ASCII files), for a message that says
// what is inconsistent: 2.2: the count, then one line each; 4.1: "blocks count min max", then per
// block a header line and one line per element, or two per node (tags, then coordinates).
void check_ascii_counts(std::string_view bytes, const std::string& name, double version) {
  Input in(bytes, name);
  std::string_view line;
  while (in.next_line(line)) {
    const bool nodes = line == "$Nodes", elements = line == "$Elements";
    if (!nodes && !elements) continue;
    const std::string section(line), end = nodes ? "$EndNodes" : "$EndElements";
    if (!in.next_line(line)) return;
    const long header_line = in.line_number();
    long blocks = 0, count = -1;
    std::istringstream head{std::string(line)};
    if (version >= 4)
      head >> blocks >> count;
    else
      head >> count;
    if (!head || count < 0 || blocks < 0) return;  // the parser reports the malformed header
    long lines = 0;
    while (in.next_line(line) && line != end) ++lines;
    if (line != end) return;  // truncated: the parser reports it
    const long per_item = nodes && version >= 4 ? 2 : 1;
    const long expected = version >= 4 ? blocks + per_item * count : count;
    if (lines != expected)
      throw MeshFileError(fmt::format(
          "{}:{}: {} declares {} {}{} but its section holds {} line{} (expected {}): the file is "
          "inconsistent",
          name, header_line, section, count, nodes ? "nodes" : "elements",
          version >= 4 ? fmt::format(" in {} blocks", blocks) : "", lines, lines == 1 ? "" : "s",
          expected));
  }
}

// $MeshFormat: "version file-type data-size", then (binary) the integer 1 in the writer's byte
// order. Returns the version and whether the file is binary.
std::pair<double, bool> read_format(Input& in) {
  std::string_view line = in.line("$MeshFormat");
  if (line != "$MeshFormat") in.fail("not a Gmsh mesh file (it must start with $MeshFormat)");
  msh::Tokens t(in.line("the format line"), in);
  const double version = t.real("the format version");
  const long file_type = t.integer("the file type");
  const long data_size = t.integer("the data size");
  if (version >= 4 && version < 4.1)
    in.fail(fmt::format("MSH {} is not read: save the mesh as MSH 4.1 or 2.2", version));
  if (!((version >= 2 && version < 3) || version == 4.1))
    in.fail(fmt::format("MSH version {} is not read (2.2 and 4.1 are)", version));
  if (file_type != 0 && file_type != 1)
    in.fail(fmt::format("file type {} (0: ASCII, 1: binary)", file_type));
  if (data_size != 8) in.fail(fmt::format("data size {} (8 expected)", data_size));
  const bool binary = file_type == 1;
  if (binary) {
    in.set_binary(true);
    const auto one = in.binary<std::int32_t>("the byte-order mark");
    if (one != 1)
      in.fail(one == 0x01000000 ? "written on a machine of the other byte order"
                                : "the byte-order mark is not 1: corrupt");
    in.end_binary_block();
  }
  if (in.line("$EndMeshFormat") != "$EndMeshFormat") in.fail("expected $EndMeshFormat here");
  return {version, binary};
}

// The sections after $MeshFormat; unknown ones ($Comments, $NodeData, ...) are skipped.
void read_sections(Input& in, bool msh41, bool binary, MshContents& out) {
  std::string_view line;
  while (in.next_line(line)) {
    if (line == "$PhysicalNames")
      msh::read_physical_names(in, out);
    else if (line == "$Entities" && msh41)
      msh::read_msh41_entities(in, binary, out);
    else if (line == "$PartitionedEntities")
      in.fail("a partitioned mesh ($PartitionedEntities): save it unpartitioned");
    else if (line == "$Nodes")
      msh41 ? msh::read_msh41_nodes(in, binary, out) : msh::read_msh2_nodes(in, binary, out);
    else if (line == "$Elements")
      msh41 ? msh::read_msh41_elements(in, binary, out) : msh::read_msh2_elements(in, binary, out);
    else if (line.size() > 1 && line.front() == '$' && line.substr(0, 4) != "$End")
      in.skip_section(line.substr(1));
    else if (!line.empty())
      in.fail(fmt::format("unexpected '{}' between sections", msh::printable(line)));
  }
}

// The file's physical groups become node sets (every dimension) and element sets (lines and
// surfaces), in the order (dimension, tag), an element belonging to the first set naming it;
// without physical groups every line and surface element goes to the set "all".
MeshData mesh_of(MshContents& c, const std::string& name) {
  MeshData mesh;
  if (c.nodes.empty()) throw MeshFileError(fmt::format("{}: the file holds no mesh nodes", name));
  for (const auto& n : c.nodes)
    if (!n.x.allFinite())
      throw MeshFileError(fmt::format("{}: node {} has a non-finite coordinate ({}, {}, {})", name,
                                      n.id, n.x.x(), n.x.y(), n.x.z()));
  mesh.nodes = std::move(c.nodes);
  // A .msh file is self-contained: every node an element names is in its $Nodes (checked here,
  // once, so that no later use of an element or node set meets an undefined node).
  std::unordered_set<long> defined;
  defined.reserve(mesh.nodes.size());
  for (const auto& n : mesh.nodes) defined.insert(n.id);
  for (const auto& b : c.elements) {
    const std::size_t per = static_cast<std::size_t>(msh::element_type(b.type)->nodes);
    for (std::size_t k = 0; k < b.nodes.size(); ++k)
      if (!defined.count(b.nodes[k]))
        throw MeshFileError(
            fmt::format("{}: element {} ({}) refers to node {}, which $Nodes does "
                        "not define",
                        name, b.tags[k / per], msh::element_type(b.type)->name, b.nodes[k]));
  }

  // A membrane model has no volumes: volume elements are refused, not dropped unseen.
  std::size_t volumes = 0;
  const msh::ElementBlock* first_volume = nullptr;
  for (const auto& b : c.elements)
    if (b.dim == 3 && !b.tags.empty()) {
      volumes += b.tags.size();
      if (!first_volume) first_volume = &b;
    }
  if (first_volume)
    throw MeshFileError(fmt::format(
        "{}: the file holds {} volume element{} (first: element {}, {}); Velum reads line and "
        "surface elements: mesh or save the surfaces only",
        name, volumes, volumes == 1 ? "" : "s", first_volume->tags.front(),
        msh::element_type(first_volume->type)->name));

  // Blocks in the order of their entity, then type.
  std::vector<const msh::ElementBlock*> blocks;
  for (const auto& b : c.elements) blocks.push_back(&b);
  std::stable_sort(blocks.begin(), blocks.end(), [](const auto* a, const auto* b) {
    return std::tie(a->dim, a->entity, a->type) < std::tie(b->dim, b->entity, b->type);
  });

  std::set<long> claimed;
  auto add_block = [&](const std::string& set, const msh::ElementBlock& b) {
    const std::string type = type_of_gmsh(b.type);
    if (type.empty())
      throw MeshFileError(fmt::format(
          "{}: set '{}': Gmsh element type {} ({}) is not supported (tri3 tri6 quad4 quad8 "
          "quad9 line2 line3)",
          name, set, b.type, msh::element_type(b.type)->name));
    ElementGroup* g = nullptr;
    for (auto& h : mesh.groups)
      if (h.set == set && h.type == type) g = &h;
    if (!g) {
      mesh.groups.push_back({set, type, {}, {}, 0});
      g = &mesh.groups.back();
    }
    const std::size_t n = static_cast<std::size_t>(msh::element_type(b.type)->nodes);
    for (std::size_t e = 0; e < b.tags.size(); ++e) {
      if (!claimed.insert(b.tags[e]).second) continue;
      g->ids.push_back(b.tags[e]);
      g->node_ids.insert(g->node_ids.end(), b.nodes.begin() + static_cast<long>(e * n),
                         b.nodes.begin() + static_cast<long>((e + 1) * n));
    }
  };

  std::set<std::pair<int, int>> groups;  // (dim, physical tag)
  for (const auto& [entity, physicals] : c.entity_physicals)
    for (int p : physicals) groups.insert({entity.first, p});
  for (const auto& group : groups) {
    const int dim = group.first, tag = group.second;  // captured below (C++20 bindings are not)
    const auto named = c.physical_names.find({dim, tag});
    const std::string set = named != c.physical_names.end() && !named->second.empty()
                                ? named->second
                                : std::to_string(tag);
    auto in_group = [&](int d, int entity) {
      const auto it = c.entity_physicals.find({d, entity});
      return d == dim && it != c.entity_physicals.end() && it->second.count(tag) > 0;
    };
    std::vector<long> nodes;
    for (const auto* b : blocks)
      if (in_group(b->dim, b->entity)) nodes.insert(nodes.end(), b->nodes.begin(), b->nodes.end());
    if (dim == 0)  // a physical point: its entity's nodes, with or without a point element
      for (const auto& nb : c.node_blocks)
        if (in_group(nb.dim, nb.entity))
          for (std::size_t i = nb.first; i < nb.first + nb.count; ++i)
            nodes.push_back(mesh.nodes[i].id);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    auto& ns = mesh.node_sets[set];
    ns.insert(ns.end(), nodes.begin(), nodes.end());
    if (dim == 1 || dim == 2)
      for (const auto* b : blocks)
        if (in_group(b->dim, b->entity)) add_block(set, *b);
  }
  if (groups.empty())
    for (int dim : {1, 2})
      for (const auto* b : blocks)
        if (b->dim == dim) add_block("all", *b);
  std::erase_if(mesh.groups, [](const ElementGroup& g) { return g.ids.empty(); });
  if (mesh.groups.empty())
    throw MeshFileError(fmt::format("{}: the file holds no line or surface elements", name));
  return mesh;
}

}  // namespace

MeshData read_gmsh_text(std::string_view bytes, const std::string& name) {
  if (bytes.substr(0, 11) != "$MeshFormat")
    throw MeshFileError(
        fmt::format("{}: not a Gmsh mesh file (it must start with $MeshFormat)", name));
  Input in(bytes, name);
  const auto [version, binary] = read_format(in);
  if (!binary) check_ascii_counts(bytes, name, version);
  try {
    MshContents contents;
    read_sections(in, version >= 4, binary, contents);
    return mesh_of(contents, name);
  } catch (const std::bad_alloc&) {
    throw MeshFileError(fmt::format("{}: the mesh is larger than this machine's memory", name));
  }
}

MeshData read_gmsh(const std::filesystem::path& file) {
  const std::string name = file.string();
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (fs::is_directory(st))
    throw MeshFileError(fmt::format("{}: is a directory, not a mesh file", name));
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw MeshFileError(fmt::format("{}: not a regular file (a device or a pipe?)", name));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw MeshFileError(fmt::format("{}: cannot open the mesh file", name));
  // The first line before the rest: a file of gigabytes that is no mesh is refused at once,
  // not after it has been read whole.
  {
    char head[11] = {};
    in.read(head, sizeof head);
    if (std::string_view(head, static_cast<size_t>(in.gcount())) != "$MeshFormat")
      throw MeshFileError(
          fmt::format("{}: not a Gmsh mesh file (it must start with $MeshFormat)", name));
    in.clear();
    in.seekg(0);
  }
  std::string bytes;
  try {
    const auto size = fs::file_size(file, ec);
    if (!ec) bytes.reserve(size);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::bad_alloc&) {
    throw MeshFileError(
        fmt::format("{}: the mesh file is larger than this machine's memory can hold", name));
  }
  if (in.bad()) throw MeshFileError(fmt::format("{}: reading the mesh file failed", name));
  return read_gmsh_text(bytes, name);
}

}  // namespace velum::io
