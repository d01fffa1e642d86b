// libFuzzer harness for the YAML model reader: each input is read as model text, in memory
// (read_model_text: the reader read_model uses once it has the file's bytes; no file is
// written, which had made a third of each execution system time); InputError (bad input,
// reported) is the expected outcome, anything else (a crash, a sanitizer report, another
// exception, a hang) is a bug. A mesh.file in the input resolves relative to an empty
// temporary folder (the Gmsh reader has its own harness).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "velum/io/model_reader.hpp"

namespace {

std::filesystem::path scratch_dir() {
  auto d = std::filesystem::temp_directory_path() / ("velum-fuzz-" + std::to_string(getpid()));
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const velum::io::ModelSource source{.name = "fuzz.yaml", .base_dir = scratch_dir()};
  try {
    (void)velum::io::read_model_text(std::string(reinterpret_cast<const char*>(data), size),
                                     source);
  } catch (const velum::io::InputError&) {  // NOLINT(bugprone-empty-catch): bad input, reported
  }
  return 0;
}
