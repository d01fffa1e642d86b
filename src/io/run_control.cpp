#include "velum/io/run_control.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace velum::io {
namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_interrupt(int signo) {
  g_signal = signo;
}

}  // namespace

void say_text(std::FILE* f, const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fflush(f) != 0)
    std::clearerr(f);
}

void prepare_standard_streams() {
  for (int fd = 0; fd <= 2; ++fd)
    if (fcntl(fd, F_GETFD) == -1 && errno == EBADF) {
      const int n = open("/dev/null", O_RDWR);  // the lowest free descriptor: fd
      if (n >= 0 && n != fd) close(n);
    }
  std::signal(SIGPIPE, SIG_IGN);
}

InterruptGuard::InterruptGuard() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second signal acts as usual (ends the process)
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

int InterruptGuard::signal_received() {
  return g_signal;
}

OutputLock::OutputLock(const std::filesystem::path& directory) {
  const auto file = directory / ".velum.lock";
  fd_ = open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    why_not_ = fmt::format("cannot open {}: {}", file.string(), std::strerror(errno));
    return;
  }
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) {
      char buf[32] = {};
      const ssize_t n = pread(fd_, buf, sizeof buf - 1, 0);
      why_not_ = fmt::format(
          "another velum run{} is writing into it ({} is locked)",
          n > 0 ? fmt::format(" (pid {})", std::string(buf, static_cast<size_t>(n))) : "",
          file.string());
    } else {
      why_not_ = fmt::format("cannot lock {}: {}", file.string(), std::strerror(errno));
    }
    return;
  }
  held_ = true;
  const std::string pid = std::to_string(getpid());
  if (ftruncate(fd_, 0) == 0 && pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is for messages only.
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) close(fd_);  // releases the lock
}

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace velum::io
