#include "velum/run/fit_command.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "run_parts.hpp"
#include "velum/config.hpp"
#include "velum/io/run_control.hpp"

namespace velum::run {
namespace {

// The build tree's package folder (python/velum/fit.py beside the executable), if there.
std::string build_tree_package_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const auto dir = exe.parent_path() / "python";
  return std::filesystem::is_regular_file(dir / "velum" / "fit.py", ec) ? dir.string()
                                                                        : std::string();
}

}  // namespace

int fit_command(const std::vector<std::string>& args) {
  // velum.fit is a module of Velum's Python package, which imports the compiled core: a build
  // without it (VELUM_WITH_PYTHON off, or no pybind11) cannot fit.
  if (!VELUM_HAVE_PYTHON) {
    say(stderr,
        "error: velum fit needs Velum's Python package, which this build does not have "
        "(configure with VELUM_WITH_PYTHON=ON; Debian: apt-get install pybind11-dev "
        "python3-dev)\n");
    return kExitIo;
  }
  if (access(kPython, X_OK) != 0) {
    say(stderr,
        "error: velum fit needs {} with numpy and matplotlib (Debian: apt-get install "
        "python3-numpy python3-matplotlib)\n",
        kPython);
    return kExitIo;
  }
  std::vector<std::string> words = {"-m", "velum.fit"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<std::pair<std::string, std::string>> environment = {{"VELUM_FIT_PROG", "velum fit"}};
  if (const std::string package = build_tree_package_dir(); !package.empty()) {
    const char* old = std::getenv("PYTHONPATH");
    environment.emplace_back("PYTHONPATH", old && *old ? package + ":" + old : package);
  }
  return run_python("velum fit", std::move(words), environment);
}

}  // namespace velum::run
