#pragma once
// A splash given as recorded impacts instead of a law: the simulated cells of a grainlab-splash/1 file
// (grainlab's own 2-D or 3-D impacts; validation/recorded_splash.hpp converts the file, so this library
// stays independent of saltation/). The hybrid model draws one recorded impact of the nearest cell per
// impact on its bed and uses its rebound and its ejecta, in the frame of the bed triangle that was hit.
#include <string>
#include <vector>

namespace grainlab::ripples::hybrid {

// A velocity in sqrt(g d), in an impact's own frame: `along` the incident motion's direction in the bed
// plane, `normal` away from the bed, `across` = normal x along.
struct RecordedVelocity {
  double along = 0, normal = 0, across = 0;
};
struct RecordedEjectum {
  RecordedVelocity launch;       // launch velocity (carried back to the grain's resting height)
  double along = 0, across = 0;  // where it sat relative to the impact point, d
};
struct RecordedImpact {
  bool rebounded = false;
  RecordedVelocity rebound;
  std::vector<RecordedEjectum> ejecta;
};
struct RecordedCell {
  double speed = 0, angle_deg = 0;  // incident speed / sqrt(g d), angle below the bed plane
  std::vector<RecordedImpact> impacts;
  // One of the impacts, drawn uniformly with u in [0, 1).
  const RecordedImpact& draw(double u) const;
};

struct RecordedSplash {
  std::string source;                      // the file it came from (for reports)
  std::vector<double> speeds, angles_deg;  // the grid, ascending; cells row-major [speed][angle]
  std::vector<RecordedCell> cells;

  // Throws std::invalid_argument unless the grid is non-empty and ascending, the cells fill it, and each
  // cell holds at least one impact.
  void check() const;
  // The cell of the speed and the angle nearest the impact's, each on its own axis.
  const RecordedCell& nearest(double speed, double angle_deg) const;
};

}  // namespace grainlab::ripples::hybrid
