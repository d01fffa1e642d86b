// What a run needs from the process around it: console messages that never abort the run
// (a closed or full stdout/stderr, a reader that went away), SIGINT and SIGTERM turned into a
// request to stop after the current step, and an output directory that only one run writes.
#pragma once

#include <fmt/format.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

namespace velum::io {

/// Writes a message to `f` (stdout or stderr); a failed write is ignored: the run's results
/// matter more than its console.
void say_text(std::FILE* f, const std::string& text);

template <class... T>
void say(std::FILE* f, fmt::format_string<T...> format, T&&... args) {
  say_text(f, fmt::format(format, std::forward<T>(args)...));
}

/// Descriptors 0, 1 and 2 open (on /dev/null when a parent closed them: otherwise the first
/// results file opened would become "stdout"), and SIGPIPE ignored (a write to a closed pipe
/// fails with EPIPE instead of killing the process).
void prepare_standard_streams();

/// CPU time of this process so far (user + system, all threads), seconds.
double cpu_seconds();

/// While alive, SIGINT and SIGTERM set a flag instead of killing the process (a second one
/// kills it as usual); the previous handlers come back at destruction.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  /// The signal received (SIGINT or SIGTERM), or 0.
  static int signal_received();

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

/// An exclusive lock on DIR/.velum.lock (flock), held until destruction. The kernel releases
/// it when the process ends in any way, so a killed run never leaves the folder locked.
class OutputLock {
 public:
  explicit OutputLock(const std::filesystem::path& directory);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  bool held() const { return fd_ >= 0 && held_; }
  /// Why the lock is not held: another run's pid, or the system error.
  const std::string& why_not() const { return why_not_; }

 private:
  int fd_ = -1;
  bool held_ = false;
  std::string why_not_;
};

}  // namespace velum::io
