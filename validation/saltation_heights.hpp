#pragma once
// Fig. 4.22 as a figure and as checks: the heights grains of 0.025 and 0.1 cm reach in a sediment-free
// wind (saltation/clean_wind_heights.hpp), drawn beside the vacuum parabola v_oy^2 / 2g, and what the
// thesis reads off them: the small grains' height saturates with launch speed, the large grains rise
// higher at every speed, and at low speed both rise as in vacuum.
#include <string>
#include <vector>

#include "clean_wind_heights.hpp"
#include "report.hpp"

namespace grainlab::validation {

// The thesis's setting (u* = 160 cm/s, roughness 1 cm, d = 0.025 and 0.1 cm, vertical and 60 deg from
// it) at launch speeds 10-1000 cm/s.
saltation::CleanWindSpec fig4_22_spec();
PlotSpec clean_wind_height_plot(const std::vector<saltation::CleanWindLaunch>& launches,
                                const std::string& file = "saltation_fig4_22.png");
// A Markdown table: height per launch speed, one column per size and angle.
std::string clean_wind_height_table(const std::vector<saltation::CleanWindLaunch>& launches);
// The checks on Fig. 4.22's spec, added to the report with ids saltation/fig-4.22/...
void clean_wind_height_checks(Report& r, const std::vector<saltation::CleanWindLaunch>& launches);

}  // namespace grainlab::validation
