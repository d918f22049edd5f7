#pragma once
// Fig. 4.22 of the thesis (Ch. IV, after Sharp 1964): how high grains of two sizes rise when they are
// launched into a sediment-free wind, the log profile of eq. 4.28 over a rough surface (u* = 160 cm/s,
// roughness 1 cm: about 40 mph at 100 cm), vertically and at 60 deg to the vertical, with the drag of eqs
// 4.30-4.31. The thesis found that the small grains' height "saturates" with launch speed while the large
// ones keep rising, and read Sharp's higher-hopping coarse grains as an effect of drag, not of the splash.
#include <vector>

#include "wind_model.hpp"

namespace grainlab::saltation {

struct CleanWindSpec {
  double u_star = 160;   // cm/s
  double roughness = 1;  // cm: u = k u* ln(y / roughness) above it, still air below
  double top = 2000;     // cm: the profile's table ends here, the log law goes on above
  double grain_density = 2.6;
  Fluid fluid;
  double g = 981;
  std::vector<double> diameters{0.025, 0.1};  // cm
  std::vector<double> angles{0, 60};          // launch direction from the vertical, downwind (deg)
  std::vector<double> speeds;                 // vertical launch speeds v_oy (cm/s)
};

struct CleanWindLaunch {
  double diameter = 0, angle = 0, v_oy = 0;
  double height = 0, length = 0, time = 0;  // apex (cm), range (cm), flight time (s)
  double impact_vx = 0, impact_vy = 0;      // on landing (cm/s)
  double vacuum_height = 0;                 // v_oy^2 / 2g
};

// Every (diameter, angle, speed), in that nesting order. Throws std::invalid_argument on a spec that
// cannot be flown (non-positive sizes, speeds or roughness; an angle outside [0, 90)).
std::vector<CleanWindLaunch> clean_wind_heights(const CleanWindSpec& s);

// d ln(height) / d ln(v_oy) between the two fastest launches of one diameter and angle: 2 in vacuum, and
// falling toward 0 where the height saturates. NaN if fewer than two launches match.
double height_exponent_at_top(const std::vector<CleanWindLaunch>& launches, double diameter, double angle);

}  // namespace grainlab::saltation
