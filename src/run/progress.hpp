// The run's console: a progress bar on stderr redrawn at most ten times a second on a
// terminal, otherwise one line at the start and one at the end (the run driver's own).
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "velum/io/run_control.hpp"
#include "velum/time/time_loop.hpp"

namespace velum::run {

using Clock = std::chrono::steady_clock;
using io::say;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  if (s < 60) return fmt::format("{:.0f}s", s);
  if (s < 3600) return fmt::format("{:.0f}m{:02.0f}s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f}h{:02.0f}m", std::floor(s / 3600), std::fmod(s / 60, 60));
}

class Progress {
 public:
  Progress(bool quiet, double t0, double t_end)
      : quiet_(quiet),
        tty_(isatty(fileno(stderr)) != 0),
        t0_(t0),
        t_end_(t_end),
        start_(Clock::now()) {}

  void start(const std::string& what) {
    if (quiet_) return;
    if (!tty_) say(stderr, "velum: {} from t = {:.6g} to {:.6g}\n", what, t0_, t_end_);
  }
  void update(const AcceptedStep& s) {
    if (quiet_ || !tty_) return;
    const auto now = Clock::now();
    if (now - last_ < std::chrono::milliseconds(100) && s.t < t_end_) return;
    last_ = now;
    const double frac = std::clamp((s.t - t0_) / (t_end_ - t0_), 0.0, 1.0);
    const double elapsed = seconds_since(start_);
    const double eta = frac > 0 ? elapsed * (1 - frac) / frac : -1;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    say(stderr, "\r[{}{}] t = {:<10.4g} h = {:<9.3g} step {:<6d} newton {:<3d} ETA {:<8}",
        std::string(static_cast<size_t>(filled), '#'),
        std::string(static_cast<size_t>(kWidth - filled), '.'), s.t, s.h, s.step, s.iterations,
        duration_text(eta));
    std::fflush(stderr);
    drawn_ = true;
  }
  /// Ends the bar's line so that a message can follow.
  void end_line() {
    if (drawn_) say(stderr, "\n");
    drawn_ = false;
  }
  // A warning on its own line (the bar, if drawn, continues below it); quiet: none (it is in
  // summary.json). A console that cannot take it changes nothing.
  void warn(const std::string& w) {
    if (quiet_) return;
    if (drawn_) say(stderr, "\n");
    drawn_ = false;
    say(stderr, "warning: {}\n", w);
  }
  void finish(const TimeLoopResult& r) {
    if (quiet_) return;
    end_line();
    say(stderr,
        "velum: {} at t = {:.6g} after {} steps, {} Newton iterations ({} factorisations), {} "
        "cut-backs, {:.2f} s\n",
        r.completed ? "finished" : "stopped", r.t, r.steps, r.iterations, r.factorizations,
        r.cutbacks, seconds_since(start_));
  }

 private:
  bool quiet_, tty_;
  double t0_, t_end_;
  Clock::time_point start_, last_{};
  bool drawn_ = false;
};

}  // namespace velum::run
