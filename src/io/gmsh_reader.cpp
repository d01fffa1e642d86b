#include <fmt/format.h>
#include <gmsh.h>
#include <omp.h>

#include <fstream>
#include <new>
#include <set>
#include <sstream>
#include <string_view>

#include "velum/io/mesh_data.hpp"

namespace velum::io {

std::string type_of_gmsh(int gmsh_type) {
  switch (gmsh_type) {
    case 1:
      return "cable2";
    case 2:
      return "tri3";
    case 3:
      return "quad4";
    case 8:
      return "cable3";
    case 9:
      return "tri6";
    case 10:
      return "quad9";
    case 16:
      return "quad8";
    default:
      return {};
  }
}

namespace {

// The Gmsh library keeps global state: one session at a time, always finalised. Its
// initialisation also sets the OpenMP thread count of the calling thread to its own option
// General.NumThreads (1), which would leave every later parallel region of the run on one
// thread: the session puts the count back.
class GmshSession {
 public:
  GmshSession() : threads_(omp_get_max_threads()) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 0);
    gmsh::option::setNumber("General.AbortOnError", 3);  // errors throw
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // NOLINT(bugprone-empty-catch): nothing to do at teardown
    }
    omp_set_num_threads(threads_);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  int threads_;
};

std::string last_gmsh_error() {
  std::string e;
  try {
    gmsh::logger::getLastError(e);
  } catch (...) {  // NOLINT(bugprone-empty-catch)
  }
  return e;
}

// Gmsh reads as many nodes and elements as a section's header declares and skips the rest
// silently, or stops short: an ASCII file's sections are counted here line by line against
// their headers (2.2: the count, then one line each; 4.x: "blocks count min max", then per
// block a header line and one line per element, or two per node: tags, then coordinates).
// Binary files are left to Gmsh.
void check_ascii_counts(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  long number = 0;
  double version = 0;
  int file_type = 0;
  auto next = [&]() {
    ++number;
    if (!std::getline(in, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  while (next()) {
    if (line == "$MeshFormat") {
      if (!next()) return;
      std::istringstream(line) >> version >> file_type;
      if (file_type != 0) return;  // binary
      continue;
    }
    const bool nodes = line == "$Nodes", elements = line == "$Elements";
    if (!nodes && !elements) continue;
    const std::string section = line, end = nodes ? "$EndNodes" : "$EndElements";
    const long header_line = number + 1;
    if (!next()) return;
    long blocks = 0, count = -1;
    std::istringstream head(line);
    if (version >= 4)
      head >> blocks >> count;
    else
      head >> count;
    if (!head || count < 0 || blocks < 0) return;  // Gmsh reports the malformed header
    long lines = 0;
    while (next() && line != end) ++lines;
    if (line != end) return;                                 // truncated: Gmsh reports it
    const long per_item = nodes && version >= 4.05 ? 2 : 1;  // 4.0: "tag x y z" lines
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

MeshData read_open_model(const std::string& name) {
  MeshData mesh;
  std::vector<std::size_t> tags;
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, false, false);
  if (tags.empty()) throw MeshFileError(fmt::format("{}: the file holds no mesh nodes", name));
  if (coord.size() != 3 * tags.size())
    throw MeshFileError(fmt::format("{}: inconsistent node data", name));
  mesh.nodes.reserve(tags.size());
  for (size_t i = 0; i < tags.size(); ++i) {
    const Vec3 x(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]);
    if (!x.allFinite())
      throw MeshFileError(fmt::format("{}: node {} has a non-finite coordinate ({}, {}, {})", name,
                                      tags[i], x.x(), x.y(), x.z()));
    mesh.nodes.push_back({static_cast<long>(tags[i]), x});
  }

  std::set<std::size_t> claimed;  // an element belongs to the first element set naming it
  auto add_elements = [&](const std::string& set, int dim, int entity) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> etags, ntags;
    gmsh::model::mesh::getElements(types, etags, ntags, dim, entity);
    for (size_t k = 0; k < types.size(); ++k) {
      const std::string type = type_of_gmsh(types[k]);
      if (type.empty()) {
        std::string ename;
        int edim = 0, order = 0, nn = 0, nprim = 0;
        std::vector<double> lc;
        gmsh::model::mesh::getElementProperties(types[k], ename, edim, order, nn, lc, nprim);
        throw MeshFileError(fmt::format(
            "{}: set '{}': Gmsh element type {} ({}) is not supported (tri3 tri6 quad4 quad8 "
            "quad9 line2 line3)",
            name, set, types[k], ename));
      }
      const size_t n = ntags[k].size() / std::max<size_t>(etags[k].size(), 1);
      ElementGroup* g = nullptr;
      for (auto& h : mesh.groups)
        if (h.set == set && h.type == type) g = &h;
      if (!g) {
        mesh.groups.push_back({set, type, {}, {}, 0});
        g = &mesh.groups.back();
      }
      for (size_t e = 0; e < etags[k].size(); ++e) {
        if (!claimed.insert(etags[k][e]).second) continue;
        g->ids.push_back(static_cast<long>(etags[k][e]));
        for (size_t i = 0; i < n; ++i)
          g->node_ids.push_back(static_cast<long>(ntags[k][e * n + i]));
      }
    }
  };

  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    std::string set;
    gmsh::model::getPhysicalName(dim, tag, set);
    if (set.empty()) set = std::to_string(tag);
    std::vector<std::size_t> ntags;
    std::vector<double> c;
    gmsh::model::mesh::getNodesForPhysicalGroup(dim, tag, ntags, c);
    auto& ns = mesh.node_sets[set];
    for (auto t : ntags) ns.push_back(static_cast<long>(t));
    if (dim == 1 || dim == 2) {
      std::vector<int> entities;
      gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
      for (int ent : entities) add_elements(set, dim, ent);
    }
  }
  if (groups.empty()) {
    for (int dim : {1, 2}) add_elements("all", dim, -1);
  }
  std::erase_if(mesh.groups, [](const ElementGroup& g) { return g.ids.empty(); });
  if (mesh.groups.empty())
    throw MeshFileError(fmt::format("{}: the file holds no line or surface elements", name));
  return mesh;
}

}  // namespace

MeshData read_gmsh(const std::filesystem::path& file) {
  const std::string name = file.string();
  {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto st = fs::status(file, ec);
    if (fs::is_directory(st))
      throw MeshFileError(fmt::format("{}: is a directory, not a mesh file", name));
    if (fs::exists(st) && !fs::is_regular_file(st))
      throw MeshFileError(fmt::format("{}: not a regular file (a device or a pipe?)", name));
    std::ifstream in(file, std::ios::binary);
    if (!in) throw MeshFileError(fmt::format("{}: cannot open the mesh file", name));
    char first[12] = {};
    in.read(first, sizeof first - 1);
    if (std::string_view(first).rfind("$MeshFormat", 0) != 0)
      throw MeshFileError(
          fmt::format("{}: not a Gmsh mesh file (it must start with $MeshFormat)", name));
  }
  check_ascii_counts(file, name);
  GmshSession session;
  try {
    gmsh::open(name);
  } catch (const std::bad_alloc&) {
    // libgmsh sizes its arrays from the file's counts unchecked (binary files: 4 TB asked for
    // by one flipped byte, found by fuzzing).
    throw MeshFileError(fmt::format(
        "{}: cannot read the Gmsh file: the Gmsh library ran out of memory reading it (a count "
        "in the file is larger than this machine can hold: a corrupt file?)",
        name));
  } catch (const std::exception& e) {
    const std::string why = last_gmsh_error();
    throw MeshFileError(
        fmt::format("{}: cannot read the Gmsh file: {}", name, why.empty() ? e.what() : why));
  } catch (...) {
    const std::string why = last_gmsh_error();
    throw MeshFileError(fmt::format("{}: cannot read the Gmsh file: {}", name,
                                    why.empty() ? "unknown error" : why));
  }
  const std::string why = last_gmsh_error();
  if (!why.empty())
    throw MeshFileError(
        fmt::format("{}: cannot read the Gmsh file (truncated or corrupt?): {}", name, why));
  try {
    return read_open_model(name);
  } catch (const MeshFileError&) {
    throw;
  } catch (const std::exception& e) {
    throw MeshFileError(fmt::format("{}: cannot read the Gmsh file: {}", name, e.what()));
  } catch (...) {
    throw MeshFileError(fmt::format("{}: cannot read the Gmsh file", name));
  }
}

}  // namespace velum::io
