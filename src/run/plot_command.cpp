#include "velum/run/plot_command.hpp"

#include <unistd.h>

#include "run_parts.hpp"
#include "velum/io/run_control.hpp"

namespace velum::run {
namespace {

constexpr const char* kScript = "velum_plot.py";

}  // namespace

std::optional<std::filesystem::path> plot_script() {
  return share_script(kScript);
}

std::optional<std::filesystem::path> share_script(const char* name) {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  const auto here = exe.parent_path();
  for (const auto& candidate : {here / "share" / "velum" / name,                   // build tree
                                here.parent_path() / "share" / "velum" / name}) {  // installed
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
  }
  return std::nullopt;
}

int plot_command(const std::vector<std::string>& args) {
  const auto script = plot_script();
  if (!script) {
    say(stderr,
        "error: velum plot: {} is not installed beside this executable (share/velum/ or "
        "../share/velum/): build or install Velum again\n",
        kScript);
    return kExitIo;
  }
  if (access(kPython, X_OK) != 0) {
    say(stderr,
        "error: velum plot needs {} with matplotlib and meshio (Debian: apt-get install "
        "python3-matplotlib python3-meshio)\n",
        kPython);
    return kExitIo;
  }
  std::vector<std::string> words = {script->string()};
  words.insert(words.end(), args.begin(), args.end());
  return run_python("velum plot", std::move(words));
}

}  // namespace velum::run
