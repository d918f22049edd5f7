#pragma once
// A progress bar on stderr for long runs: on a terminal, shown after the first second and redrawn at
// most ten times a second; when stderr goes to a file (nohup, a batch job's log), one plain line a minute
// from the first minute on, so a run of hours shows in its log how far it is.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "time_left.hpp"

namespace grainlab::cli {

class ProgressBar {
 public:
  // unit: "" shows done as a time in seconds; otherwise as a count ("runs").
  explicit ProgressBar(bool enabled, std::string unit = "")
      : enabled_(enabled), terminal_(enabled && ::isatty(STDERR_FILENO)), unit_(std::move(unit)) {}
  ~ProgressBar() { finish(); }

  // A `done` below the last one starts a new task: the clock (and the estimate of time left) restarts.
  // `extra`: a few words on the state of the run, shown after the estimate (e.g. "5120 grains airborne");
  // on a terminal the rest of the line is cleared, since the words may get shorter.
  void update(double done, double total, const std::string& extra = "") {
    update_weighted(done, total, done, total, extra);
  }
  // The same, for units of unequal size: the counts are shown ("3 of 13 suites"), while the bar and the
  // time left follow `work` (each unit weighted by its typical cost), so that a long unit finished first
  // does not make the rest look as long.
  void update_weighted(double done, double total, double work, double work_total,
                       const std::string& extra = "") {
    if (!enabled_) return;
    if (work < last_done_) start_ = clock::now();
    if (!counting_ || work < last_done_) counting_ = true, first_ = clock::now(), pace_.restart();
    last_done_ = work;
    const double counted = seconds_since(first_);
    pace_.add(counted, work);
    const double elapsed = seconds_since(start_);
    const double every = terminal_ ? 0.1 : 60.0, first = terminal_ ? 1.0 : 60.0;
    if (elapsed < first || seconds_since(last_) < every) return;
    last_ = clock::now();
    const double f = work_total > 0 ? std::min(1.0, work / work_total) : 1.0;
    const int width = 30, filled = static_cast<int>(f * width);
    const double left = pace_.left(counted, work, work_total);
    const std::string where = unit_.empty()
                                  ? fmt_number("t = %.4g s", done)
                                  : fmt_number("%.0f", done) + fmt_number(" of %.0f ", total) + unit_;
    if (!terminal_) {
      std::fprintf(stderr, "progress: %5.1f%%  %s  elapsed %s  left %s%s%s\n", 100 * f, where.c_str(),
                   clock_text(elapsed).c_str(), clock_text(left).c_str(), extra.empty() ? "" : "  ",
                   extra.c_str());
      return;
    }
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  %s  elapsed %s  left %s %s\x1b[K",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), 100 * f,
                 where.c_str(), clock_text(elapsed).c_str(), clock_text(left).c_str(),
                 extra.empty() ? "" : (extra + " ").c_str());
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
  static std::string fmt_number(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
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
  bool enabled_, terminal_;
  std::string unit_;
  double last_done_ = 0;  // in work
  RecentPace pace_;       // of this task, from its first update (so a run continued part-way counts
                          // only what this clock saw done)
  bool drawn_ = false, counting_ = false;
  clock::time_point start_ = clock::now(), last_ = clock::now() - std::chrono::seconds(1), first_ = start_;
};

}  // namespace grainlab::cli
