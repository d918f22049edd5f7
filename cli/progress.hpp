#pragma once
// A progress bar on stderr for long runs: shown only on a terminal, only after the first second,
// and redrawn at most ten times a second.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace grainlab::cli {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO)) {}
  ~ProgressBar() { finish(); }

  void update(double done, double total) {
    if (!enabled_) return;
    const double elapsed = seconds_since(start_);
    if (elapsed < 1.0 || seconds_since(last_) < 0.1) return;
    last_ = clock::now();
    const double f = total > 0 ? std::min(1.0, done / total) : 1.0;
    const int width = 30, filled = static_cast<int>(f * width);
    const double left = f > 0 ? elapsed * (1 - f) / f : 0;
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  t = %.4g s  elapsed %s  left %s ",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), 100 * f, done,
                 clock_text(elapsed).c_str(), clock_text(left).c_str());
    drawn_ = true;
  }
  void finish() {
    if (drawn_) std::fputc('\n', stderr);
    drawn_ = false;
  }

 private:
  using clock = std::chrono::steady_clock;
  static double seconds_since(clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
  }
  static std::string clock_text(double s) {
    char buf[32];
    const int h = static_cast<int>(s / 3600), m = static_cast<int>(s / 60) % 60,
              sec = static_cast<int>(s) % 60;
    if (h > 0)
      std::snprintf(buf, sizeof buf, "%dh%02dm", h, m);
    else
      std::snprintf(buf, sizeof buf, "%dm%02ds", m, sec);
    return buf;
  }
  bool enabled_;
  bool drawn_ = false;
  clock::time_point start_ = clock::now(), last_ = clock::now() - std::chrono::seconds(1);
};

}  // namespace grainlab::cli
