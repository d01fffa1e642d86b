// The velum command line (placeholder until the CLI issue lands the model-file commands).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "velum/config.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Velum: geometrically nonlinear dynamics of anisotropic membranes and cables"};
  app.set_version_flag("--version", std::string("velum ") + VELUM_VERSION);
  CLI11_PARSE(app, argc, argv);
  fmt::print("{}", app.help());
  return 0;
}
