// libFuzzer harness for Velum's Gmsh .msh reader (read_gmsh_text, src/io/gmsh): MSH 2.2 and 4.1,
// ASCII and binary, read from memory. MeshFileError is the expected outcome for a bad file;
// anything else (a crash, a leak, an allocation beyond -rss_limit_mb, a hang) is a finding.
#include <cstdint>
#include <string_view>

#include "velum/io/mesh_data.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)velum::io::read_gmsh_text(std::string_view(reinterpret_cast<const char*>(data), size),
                                    "fuzz.msh");
  } catch (const velum::io::MeshFileError&) {  // NOLINT(bugprone-empty-catch): reported
  }
  return 0;
}
