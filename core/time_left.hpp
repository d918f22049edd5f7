#pragma once
// The wall time a long task has left, at the rate it has kept since it was `first` done (in its own
// units: simulated seconds, runs), `elapsed` seconds ago. A task continued from a checkpoint starts
// part-way: the part done before took none of this clock's time (a paper-sized run resumed at 12 % once
// showed "left 7m" with 8 hours to go). 0 while nothing has been done since `first`, or past the end.
#include <algorithm>
#include <deque>
#include <utility>

namespace grainlab {

inline double time_left(double elapsed, double first, double done, double total) {
  return done > first ? elapsed * std::max(0.0, total - done) / (done - first) : 0;
}

// The time left at the pace of the recent past. A run of hours on a shared machine slows down and speeds
// up as other work comes and goes, and its pace since the start then says little about what is left
// (a paper-sized run, slowed to a crawl for half an hour by a test suite, went on to show 13 hours left
// where 4 were). Samples of (seconds, done) are kept at most `spacing` apart; the pace is taken from the
// newest one at least `window` old, or from the first while the task is younger than that.
class RecentPace {
 public:
  explicit RecentPace(double window = 600, double spacing = 10) : window_(window), spacing_(spacing) {}
  // A new task (or the same one from a checkpoint): the first sample after this one is the start.
  void restart() { samples_.clear(); }
  void add(double seconds, double done) {
    if (samples_.empty() || seconds - samples_.back().first >= spacing_) samples_.emplace_back(seconds, done);
    while (samples_.size() > 1 && seconds - samples_[1].first >= window_) samples_.pop_front();
  }
  double left(double seconds, double done, double total) const {
    if (samples_.empty()) return 0;
    const auto& [from_seconds, from_done] = samples_.front();
    return time_left(seconds - from_seconds, from_done, done, total);
  }

 private:
  double window_, spacing_;
  std::deque<std::pair<double, double>> samples_;
};

}  // namespace grainlab
