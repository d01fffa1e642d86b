// Velum's .msh reader against the Gmsh library as the oracle: meshes made by the library (line,
// triangle and quadrilateral elements of order 1 and 2, physical groups of every dimension,
// named and unnamed, and none) are written in MSH 2.2 and 4.1, ASCII and binary, and read
// both by read_gmsh and through the library's API the way Velum read them before its own
// reader; the nodes, element groups and node sets must be the same.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "velum/io/mesh_data.hpp"

namespace velum::io {
namespace {

// The Gmsh library's view of the open model, as read_gmsh gave it when it used the library.
MeshData read_through_library() {
  MeshData mesh;
  std::vector<std::size_t> tags;
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, false, false);
  for (std::size_t i = 0; i < tags.size(); ++i)
    mesh.nodes.push_back(
        {static_cast<long>(tags[i]), Vec3(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2])});
  std::set<std::size_t> claimed;
  auto add_elements = [&](const std::string& set, int dim, int entity) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> etags, ntags;
    gmsh::model::mesh::getElements(types, etags, ntags, dim, entity);
    for (std::size_t k = 0; k < types.size(); ++k) {
      const std::string type = type_of_gmsh(types[k]);
      const std::size_t n = ntags[k].size() / std::max<std::size_t>(etags[k].size(), 1);
      ElementGroup* g = nullptr;
      for (auto& h : mesh.groups)
        if (h.set == set && h.type == type) g = &h;
      if (!g) {
        mesh.groups.push_back({set, type, {}, {}, 0});
        g = &mesh.groups.back();
      }
      for (std::size_t e = 0; e < etags[k].size(); ++e) {
        if (!claimed.insert(etags[k][e]).second) continue;
        g->ids.push_back(static_cast<long>(etags[k][e]));
        for (std::size_t i = 0; i < n; ++i)
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
  if (groups.empty())
    for (int dim : {1, 2}) add_elements("all", dim, -1);
  std::erase_if(mesh.groups, [](const ElementGroup& g) { return g.ids.empty(); });
  return mesh;
}

void expect_same(const MeshData& ours, const MeshData& library, const std::string& what) {
  SCOPED_TRACE(what);
  // Node order: the library's is by tag; ours is the file's.
  auto by_id = [](std::vector<MeshNode> v) {
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
    return v;
  };
  const auto a = by_id(ours.nodes), b = by_id(library.nodes);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].id, b[i].id);
    ASSERT_EQ(a[i].x, b[i].x) << "node " << a[i].id;
  }
  ASSERT_EQ(ours.groups.size(), library.groups.size());
  for (std::size_t g = 0; g < ours.groups.size(); ++g) {
    EXPECT_EQ(ours.groups[g].set, library.groups[g].set);
    EXPECT_EQ(ours.groups[g].type, library.groups[g].type);
    EXPECT_EQ(ours.groups[g].ids, library.groups[g].ids);
    EXPECT_EQ(ours.groups[g].node_ids, library.groups[g].node_ids);
  }
  ASSERT_EQ(ours.node_sets.size(), library.node_sets.size());
  for (const auto& [name, ids] : library.node_sets) {
    ASSERT_TRUE(ours.node_sets.count(name)) << name;
    const std::set<long> x(ours.node_sets.at(name).begin(), ours.node_sets.at(name).end()),
        y(ids.begin(), ids.end());
    EXPECT_EQ(x, y) << name;
  }
}

// A unit square, 4 x 3 divisions: its surface, two curves with line elements and one corner in
// physical groups (the second curve and the corner's group unnamed) or none.
void make_model(bool quads, int order, bool physical_groups) {
  gmsh::clear();
  gmsh::model::add("square");
  namespace geo = gmsh::model::geo;
  const int p1 = geo::addPoint(0, 0, 0), p2 = geo::addPoint(1, 0, 0), p3 = geo::addPoint(1, 1, 0),
            p4 = geo::addPoint(0, 1, 0);
  const int c1 = geo::addLine(p1, p2), c2 = geo::addLine(p2, p3), c3 = geo::addLine(p3, p4),
            c4 = geo::addLine(p4, p1);
  const int loop = geo::addCurveLoop({c1, c2, c3, c4});
  const int s = geo::addPlaneSurface({loop});
  for (int c : {c1, c3}) geo::mesh::setTransfiniteCurve(c, 5);
  for (int c : {c2, c4}) geo::mesh::setTransfiniteCurve(c, 4);
  geo::mesh::setTransfiniteSurface(s);
  if (quads) geo::mesh::setRecombine(2, s);
  geo::synchronize();
  if (physical_groups) {
    const int sheet = gmsh::model::addPhysicalGroup(2, {s});
    gmsh::model::setPhysicalName(2, sheet, "sheet");
    const int edge = gmsh::model::addPhysicalGroup(1, {c1});
    gmsh::model::setPhysicalName(1, edge, "edge");
    gmsh::model::addPhysicalGroup(1, {c2, c3}, 7);  // unnamed: the set is named "7"
    gmsh::model::addPhysicalGroup(0, {p3}, 9);
  }
  gmsh::option::setNumber("Mesh.SaveAll", physical_groups ? 0 : 1);
  gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 0);
  gmsh::model::mesh::generate(2);
  if (order == 2) gmsh::model::mesh::setOrder(2);
}

TEST(GmshReader, ReadsWhatTheGmshLibraryReads) {
  const int threads = omp_get_max_threads();  // gmsh::initialize sets its own count
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
  const auto dir = std::filesystem::temp_directory_path() / "velum_gmsh_reader_test";
  std::filesystem::create_directories(dir);
  int compared = 0;
  for (bool quads : {false, true})
    for (int order : {1, 2})
      for (bool physical : {true, false})
        for (double version : {2.2, 4.1})
          for (int binary : {0, 1}) {
            make_model(quads, order, physical);
            gmsh::option::setNumber("Mesh.MshFileVersion", version);
            gmsh::option::setNumber("Mesh.Binary", binary);
            const auto file = dir / "mesh.msh";
            gmsh::write(file.string());
            const MeshData ours = read_gmsh(file);
            gmsh::clear();
            gmsh::open(file.string());
            const MeshData library = read_through_library();
            expect_same(ours, library,
                        std::string(quads ? "quad" : "tri") + std::to_string(order == 2 ? 9 : 3) +
                            (physical ? " groups" : " no groups") + " MSH " +
                            std::to_string(version) + (binary ? " binary" : " ASCII"));
            ASSERT_FALSE(ours.groups.empty());
            ++compared;
          }
  gmsh::finalize();
  omp_set_num_threads(threads);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(compared, 32);
}

TEST(GmshReader, GroupsOfTheTestMeshes) {
  // tests/cli/data/square_quad4_v41.msh: 9 nodes, 4 quads in "sheet", 2 lines in "left", the
  // node 3 in "corner".
  const auto data = std::filesystem::path(VELUM_SOURCE_DIR) / "tests/cli/data";
  for (const char* name : {"square_quad4_v41.msh", "square_quad4_v22.msh"}) {
    SCOPED_TRACE(name);
    const MeshData m = read_gmsh(data / name);
    EXPECT_EQ(m.nodes.size(), 9u);
    ASSERT_GE(m.groups.size(), 1u);
    std::size_t quads = 0;
    for (const auto& g : m.groups)
      if (g.type == "quad4") quads += g.ids.size();
    EXPECT_EQ(quads, 4u);
  }
}

TEST(GmshReader, RefusesCountsBeyondTheFile) {
  // A binary MSH 4.1 $Nodes header declaring 2^40 nodes in a file of a few hundred bytes: the
  // reader must refuse it before sizing anything from it.
  std::string file = "$MeshFormat\n4.1 1 8\n";
  const std::int32_t one = 1;
  file.append(reinterpret_cast<const char*>(&one), 4);
  file += "\n$EndMeshFormat\n$Nodes\n";
  const std::uint64_t head[4] = {1, std::uint64_t{1} << 40, 1, std::uint64_t{1} << 40};
  file.append(reinterpret_cast<const char*>(head), sizeof head);
  try {
    (void)read_gmsh_text(file, "huge.msh");
    FAIL() << "accepted";
  } catch (const MeshFileError& e) {
    EXPECT_NE(std::string(e.what()).find("huge.msh: byte"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("too short"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace velum::io
