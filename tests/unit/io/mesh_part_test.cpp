// A part of a split model (io/mesh_part.hpp): written and read back exactly; a damaged part
// refused with its file and line.
#include "velum/io/mesh_part.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace velum::io {
namespace {

MeshPart sample() {
  MeshPart p;
  p.part = 1;
  p.parts = 3;
  p.global_nodes = 10;
  p.size = 1.0 / 3.0;
  p.element_cut = 2;
  p.node_id = {4, 7, 12};
  p.global_node = {2, 5, 9};
  p.X.resize(3, 3);
  p.X << 0.1, 0.2, 1.0 / 7.0, -3e-17, 5.0, 6.0, 1e300, -0.0, 2.5;
  p.kept = {1, 0, 1};
  p.lone = {};
  p.bare = {2};
  p.shared = {0, 2};
  p.neighbours = {0, 2};
  p.shared_with = {{0}, {0, 1}};
  MeshPart::Numbering n;
  n.global_equations = 20;
  n.whole_nodes = false;
  n.equation = {0, 1, 2, -1, -1, 5, 17, 18, 19};
  n.path_equation = 5;
  n.edge_loads = {{{0, 3, 1}, {0, 4, 2}}, {}};
  p.numberings = {n, n};
  p.numberings[1].path_equation = -1;
  MeshPart::Group g;
  g.set = "the sheet";  // a name with a blank
  g.type = "quad4";
  g.whole = 6;
  g.own = {3, 4};
  g.ids = {104, 105};
  g.node_ids = {4, 7, 12, 4, 7, 12, 4, 7};
  p.groups = {g, MeshPart::Group{"lines", "cable2", 2, {}, {}, {}}};
  p.node_sets = {{"left", {4, 12}}, {"\"quoted\"", {}}};
  p.element_set_nodes = {{"the sheet", {4, 7, 12}}};
  p.history = {{0, 3, {0.25, -0.5}}, {}};
  p.points = {{99, Vec3(1, 2, 3)}};
  return p;
}

TEST(MeshPart, WrittenAndReadBackExactly) {
  const auto dir = std::filesystem::temp_directory_path() / "velum_mesh_part_test";
  std::filesystem::create_directories(dir);
  const auto file = mesh_part_file(dir, 1);
  EXPECT_EQ(file.filename(), "part_1.txt");
  const MeshPart p = sample();
  write_mesh_part(file, p);
  const MeshPart q = read_mesh_part(file);
  EXPECT_EQ(q.part, 1);
  EXPECT_EQ(q.parts, 3);
  EXPECT_EQ(q.size, p.size);
  EXPECT_EQ(q.node_id, p.node_id);
  EXPECT_EQ(q.global_node, p.global_node);
  EXPECT_EQ(q.X, p.X);
  EXPECT_EQ(q.kept, p.kept);
  EXPECT_EQ(q.bare, p.bare);
  EXPECT_EQ(q.shared_with, p.shared_with);
  ASSERT_EQ(q.numberings.size(), 2u);
  EXPECT_EQ(q.numberings[0].equation, p.numberings[0].equation);
  EXPECT_EQ(q.numberings[0].path_equation, 5);
  EXPECT_FALSE(q.numberings[0].whole_nodes);
  ASSERT_EQ(q.numberings[0].edge_loads.size(), 2u);
  EXPECT_EQ(q.numberings[0].edge_loads[0][1].side, 2);
  ASSERT_EQ(q.groups.size(), 2u);
  EXPECT_EQ(q.groups[0].set, "the sheet");
  EXPECT_EQ(q.groups[0].own, p.groups[0].own);
  EXPECT_EQ(q.groups[0].node_ids, p.groups[0].node_ids);
  EXPECT_TRUE(q.groups[1].own.empty());
  EXPECT_EQ(q.node_sets, p.node_sets);
  EXPECT_EQ(q.element_set_nodes, p.element_set_nodes);
  EXPECT_EQ(q.history[0].xi[1], -0.5);
  EXPECT_EQ(q.history[1].block, -1);
  EXPECT_EQ(q.points[0].second, Vec3(1, 2, 3));
  std::filesystem::remove_all(dir);
}

TEST(MeshPart, DamagedPartNamesFileAndLine) {
  const auto dir = std::filesystem::temp_directory_path() / "velum_mesh_part_damaged";
  std::filesystem::create_directories(dir);
  const auto file = mesh_part_file(dir, 0);
  write_mesh_part(file, sample());
  std::string text;
  {
    std::ifstream in(file);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  text.replace(text.find("7 5 "), 4, "7 x ");  // line 8: the second node's global index
  {
    std::ofstream out(file);
    out << text;
  }
  try {
    (void)read_mesh_part(file);
    FAIL() << "a damaged part was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":8:"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)read_mesh_part(dir / "part_9.txt"), std::runtime_error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace velum::io
