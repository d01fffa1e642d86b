// Models that are not files (the Python module's): YAML text or an in-memory YAML node, with a
// name for messages and a base directory for relative paths.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "velum/io/model_reader_yaml.hpp"

namespace velum::io {
namespace {

constexpr const char* kModel = R"(mesh:
  file: square.msh
materials:
  m: {type: isotropic, E: 1000.0, nu: 0.3, density: 1.0}
sections:
  - {elements: '1', material: m, thickness: 0.1}  # the Gmsh physical tag
boundary:
  - {nodes: [1, 2], fix: [x, y, z]}
analysis:
  type: static
  time: {end: 1.0, step: 1.0}
)";

std::filesystem::path write_square(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "square.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                       "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
                                       "$Elements\n1\n1 3 2 1 1 1 2 3 4\n$EndElements\n";
  return dir;
}

TEST(ModelSource, TextReadsRelativePathsFromItsBaseDirectory) {
  const auto dir = write_square(std::filesystem::temp_directory_path() / "velum_model_source");
  const ModelInput in = read_model_text(kModel, {"text model", dir});
  EXPECT_EQ(in.model.num_nodes(), 4);
  EXPECT_EQ(in.output.directory, dir / "out");
  ASSERT_EQ(in.element_ids.size(), 1u);
  EXPECT_EQ(in.element_ids[0], std::vector<long>{1});
  std::filesystem::remove_all(dir);
}

TEST(ModelSource, TextMessagesNameTheSourceAndLine) {
  std::string bad = kModel;
  bad.replace(bad.find("E: 1000.0"), 9, "E: soft");
  try {
    read_model_text(bad, {"text model", "/nonexistent"});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    // The mesh file is missing from the base directory, and E is not a number.
    const auto& m = e.messages();
    EXPECT_NE(m[0].find("text model:2: mesh.file"), std::string::npos) << e.what();
    EXPECT_NE(std::find(m.begin(), m.end(), "text model:4: materials.m.E: expected a number"),
              m.end())
        << e.what();
  }
}

TEST(ModelSource, NodeBuiltInMemoryNamesTheKeyWithoutALine) {
  const auto dir = write_square(std::filesystem::temp_directory_path() / "velum_model_node");
  YAML::Node root = YAML::Load(kModel);  // then rebuilt without positions, as from Python
  YAML::Node built(YAML::NodeType::Map);
  for (const auto& kv : root) built[kv.first.Scalar()] = YAML::Clone(kv.second);
  YAML::Node material(YAML::NodeType::Map);
  material["type"] = "isotropic";
  material["E"] = "soft";
  material["nu"] = "0.3";
  material["density"] = "1";
  YAML::Node materials(YAML::NodeType::Map);
  materials["m"] = material;
  built["materials"] = materials;
  try {
    read_model(built, {"python model", dir});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.messages().size(), 1u) << e.what();
    EXPECT_EQ(e.messages()[0], "python model: materials.m.E: expected a number");
  }
  material["E"] = "1000";
  const ModelInput in = read_model(built, {"python model", dir});
  EXPECT_EQ(in.model.num_elements(), 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace velum::io
