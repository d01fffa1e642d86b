// libFuzzer harness for the Gmsh mesh reader (read_gmsh): our checks of the file (its first
// line, the ASCII section counts, the node coordinates) and what we take from the Gmsh library.
// The library itself (Debian's libgmsh, not instrumented) runs in-process: a crash inside it is
// reported like ours, but coverage guidance only sees our code. MeshFileError is the expected
// outcome for a bad file.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "velum/io/mesh_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path = [] {
    auto d = std::filesystem::temp_directory_path() / ("velum-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d / "mesh.msh";
  }();
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    (void)velum::io::read_gmsh(path);
  } catch (const velum::io::MeshFileError&) {  // NOLINT(bugprone-empty-catch): reported
  }
  return 0;
}
