// libFuzzer harness for the Abaqus/CalculiX deck reader (docs/inp-import.md): the deck read as
// a whole model (velum import: keywords, sets, materials, steps, the YAML writer) and as a
// mesh file. InpError is the expected outcome for a bad deck.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "velum/io/inp_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path = [] {
    auto d = std::filesystem::temp_directory_path() / ("velum-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d / "deck.inp";
  }();
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  std::vector<std::string> warnings;
  try {
    (void)velum::io::import_inp(path, warnings);
  } catch (const velum::io::InpError&) {  // NOLINT(bugprone-empty-catch): reported
  }
  try {
    (void)velum::io::read_inp_mesh(path, warnings);
  } catch (const velum::io::InpError&) {  // NOLINT(bugprone-empty-catch): reported
  }
  return 0;
}
