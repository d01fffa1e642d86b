// Reading a mesh through the Gmsh library must leave the run's OpenMP thread count alone:
// gmsh::initialize sets it to Gmsh's own General.NumThreads (1), which once left every run
// that read a .msh file assembling on one thread whatever --threads said.
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>
#include <fstream>

#include "velum/io/mesh_data.hpp"

namespace velum::io {
namespace {

TEST(GmshReader, KeepsTheOpenMPThreadCount) {
  const auto file = std::filesystem::temp_directory_path() / "velum_gmsh_reader_test.msh";
  std::ofstream(file) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                         "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n"
                         "$Elements\n1\n1 3 2 1 1 1 2 3 4\n$EndElements\n";
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  const MeshData mesh = read_gmsh(file);
  EXPECT_EQ(omp_get_max_threads(), 3);
  omp_set_num_threads(before);
  std::filesystem::remove(file);
  EXPECT_EQ(mesh.nodes.size(), 4u);
}

}  // namespace
}  // namespace velum::io
