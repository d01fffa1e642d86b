// libFuzzer harness for the YAML model reader: each input is written to a model file and read;
// InputError (bad input, reported) is the expected outcome, anything else (a crash, a sanitizer
// report, another exception, a hang) is a bug. A mesh.file in the input resolves relative to
// the model file's temporary folder, where no mesh exists (the Gmsh reader has its own harness).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "velum/io/model_reader.hpp"

namespace {

std::filesystem::path scratch_file(const char* name) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("velum-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / name;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = scratch_file("model.yaml");
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    (void)velum::io::read_model(path);
  } catch (const velum::io::InputError&) {  // NOLINT(bugprone-empty-catch): bad input, reported
  }
  return 0;
}
