// `velum import DECK.inp -o MODEL.yaml`: an Abaqus/CalculiX deck as a Velum model file
// (docs/inp-import.md). The written file is read back by the model reader before the command
// says it succeeded, so an import that Velum cannot run is reported here, not at `velum run`.

#include <fmt/format.h>

#include <cstdio>
#include <fstream>

#include "run_parts.hpp"
#include "velum/io/inp_reader.hpp"
#include "velum/io/run_control.hpp"
#include "velum/run/commands.hpp"

namespace velum::run {

int import_command(const std::filesystem::path& deck, const std::filesystem::path& output) {
  // The model file must not replace the deck (the same file by any path to it).
  {
    std::error_code ec;
    if (std::filesystem::exists(output, ec) && std::filesystem::equivalent(deck, output, ec)) {
      say(stderr,
          "error: {}: the output is the deck itself; give another file for the model (-o "
          "MODEL.yaml): nothing written\n",
          output.string());
      return kExitBadInput;
    }
  }
  std::vector<std::string> warnings;
  std::string yaml;
  try {
    yaml = import_inp(deck, warnings);
  } catch (const InpError& e) {
    for (const auto& w : warnings) say(stderr, "warning: {}\n", w);
    for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
    say(stderr, "velum: {} error{} in {}: nothing written\n", e.messages().size(),
        e.messages().size() == 1 ? "" : "s", deck.string());
    return kExitBadInput;
  }
  for (const auto& w : warnings) say(stderr, "warning: {}\n", w);
  {
    std::ofstream out(output, std::ios::binary | std::ios::trunc);
    out << yaml;
    out.close();
    if (!out) {
      say(stderr, "error: {}: cannot write the model file\n", output.string());
      return kExitIo;
    }
  }
  try {
    const ModelInput in = read_model(output);
    for (const auto& w : in.warnings) say(stderr, "warning: {}\n", w);
    say(stdout,
        "velum import: wrote {} from {}: {} nodes, {} elements, {} material{}, {} warning{}\n",
        output.string(), deck.string(), in.model.num_nodes(), in.model.num_elements(),
        in.materials.size(), in.materials.size() == 1 ? "" : "s", warnings.size(),
        warnings.size() == 1 ? "" : "s");
  } catch (const InputError& e) {
    for (const auto& m : e.messages()) say(stderr, "error: {}\n", m);
    say(stderr,
        "velum: the model written from {} is not valid ({} error{}); it is kept in {} "
        "for inspection\n",
        deck.string(), e.messages().size(), e.messages().size() == 1 ? "" : "s", output.string());
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace velum::run
