#pragma once
// Figures of a sand-gun run beside Tables 3.11-3.12 (like the thesis's Figs 3.28-3.30): over the rows at
// 15-16 deg, against the incident speed, grainlab's means with their 95 % intervals, with the ejecta
// counted by the run's rule and as the photographs could see them (four diameters above the top), beside
// the experiment's means. Drawn into a report folder by write_plots.
#include <vector>

#include "report.hpp"
#include "sand_gun3d.hpp"

namespace grainlab::validation {

// The ejecta at which apex the photographs could see them (diameters above the top of the bed): the
// reading docs/impacts.md sets beside the experiment ("Counting ejecta as the photographs could").
constexpr double kPhotographsSeeAbove = 4;

std::vector<PlotSpec> sand_gun_plots(const SandGunRun& run);

}  // namespace grainlab::validation
