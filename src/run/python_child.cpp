// The Python helpers of the command line (`velum plot`, `velum fit`): Debian's interpreter
// started as a child whose exit status becomes the command's.
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "run_parts.hpp"
#include "velum/io/run_control.hpp"

namespace velum::run {

int run_python(const std::string& command, std::vector<std::string> words,
               const std::vector<std::pair<std::string, std::string>>& environment) {
  std::string interpreter = kPython;
  std::vector<char*> argv{interpreter.data()};
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t child = fork();
  if (child < 0) {
    say(stderr, "error: {}: cannot start {}: {}\n", command, kPython, std::strerror(errno));
    return kExitIo;
  }
  if (child == 0) {
    for (const auto& [name, value] : environment) setenv(name.c_str(), value.c_str(), 1);
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
