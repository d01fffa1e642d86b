#include "velum/run/plot_command.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "run_parts.hpp"
#include "velum/io/run_control.hpp"

namespace velum::run {
namespace {

constexpr const char* kPython = "/usr/bin/python3";
constexpr const char* kScript = "velum_plot.py";

}  // namespace

std::optional<std::filesystem::path> plot_script() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  const auto here = exe.parent_path();
  for (const auto& candidate : {here / "share" / "velum" / kScript,                   // build tree
                                here.parent_path() / "share" / "velum" / kScript}) {  // installed
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
  std::vector<std::string> words = {kPython, script->string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t child = fork();
  if (child < 0) {
    say(stderr, "error: velum plot: cannot start {}: {}\n", kPython, std::strerror(errno));
    return kExitIo;
  }
  if (child == 0) {
    execv(kPython, argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return kExitIo;
  if (!WIFEXITED(status)) return kExitIo;
  const int code = WEXITSTATUS(status);
  return code == 127 ? kExitIo : code == 2 ? kExitBadInput : code;  // 2: argparse's usage error
  return kExitIo;
}

}  // namespace velum::run
