#include "velum/run/fit_command.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "run_parts.hpp"
#include "velum/io/run_control.hpp"

namespace velum::run {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

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
  if (access(kPython, X_OK) != 0) {
    say(stderr,
        "error: velum fit needs {} with numpy and matplotlib (Debian: apt-get install "
        "python3-numpy python3-matplotlib)\n",
        kPython);
    return kExitIo;
  }
  std::vector<std::string> words = {kPython, "-m", "velum.fit"};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const std::string package = build_tree_package_dir();
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t child = fork();
  if (child < 0) {
    say(stderr, "error: velum fit: cannot start {}: {}\n", kPython, std::strerror(errno));
    return kExitIo;
  }
  if (child == 0) {
    if (!package.empty()) {
      const char* old = std::getenv("PYTHONPATH");
      const std::string path = old && *old ? package + ":" + old : package;
      setenv("PYTHONPATH", path.c_str(), 1);
    }
    setenv("VELUM_FIT_PROG", "velum fit", 1);
    execv(kPython, argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return kExitIo;
  if (!WIFEXITED(status)) return kExitIo;
  const int code = WEXITSTATUS(status);
  return code == 127 ? kExitIo : code == 2 ? kExitBadInput : code;  // 2: argparse's usage error
}

}  // namespace velum::run
