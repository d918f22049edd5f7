#pragma once
// The wall time a long task has left, at the rate it has kept since it was `first` done (in its own
// units: simulated seconds, runs), `elapsed` seconds ago. A task continued from a checkpoint starts
// part-way: the part done before took none of this clock's time (a paper-sized run resumed at 12 % once
// showed "left 7m" with 8 hours to go). 0 while nothing has been done since `first`, or past the end.
#include <algorithm>

namespace grainlab {

inline double time_left(double elapsed, double first, double done, double total) {
  return done > first ? elapsed * std::max(0.0, total - done) / (done - first) : 0;
}

}  // namespace grainlab
