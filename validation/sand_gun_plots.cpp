#include "sand_gun_plots.hpp"

#include <fmt/format.h>

namespace grainlab::validation {

namespace {
// One figure: `key` against v_i over the speed series. The series are offset by a few cm/s so their
// error bars do not hide each other.
PlotSpec figure(const SandGunRun& run, const std::vector<std::map<std::string, MeanInterval>>& seen,
                const std::string& key, const std::string& file, const std::string& title,
                const std::string& ylabel, bool ejecta) {
  PlotSpec p{file, title, "incident speed v_i (cm/s), rows at 15-16 deg", ylabel, false, {}};
  PlotSpec::Series ours{
      fmt::format("grainlab, ejecta counted {:g} d up (95 %)", run.visible_above), "points", {}, {}, {}},
      photographed{fmt::format("grainlab, counted {:g} d up, as the photographs could see (95 %)",
                               kPhotographsSeeAbove),
                   "points",
                   {},
                   {},
                   {}},
      experiment{"experiment (its sd where the tables give one)", "points", {}, {}, {}};
  if (!ejecta) ours.label = "grainlab (95 %)";
  for (std::size_t i : sand_gun_speed_series(run)) {
    const double v = run.rows[i].speed;
    const MeanInterval& m = run.quantities[i].at(key);
    ours.x.push_back(v - 8), ours.y.push_back(m.mean), ours.err.push_back(m.half_width());
    if (ejecta && run.visible_above != kPhotographsSeeAbove) {
      const MeanInterval& s = seen[i].at(key);
      photographed.x.push_back(v + 8), photographed.y.push_back(s.mean),
          photographed.err.push_back(s.half_width());
    }
    experiment.x.push_back(v), experiment.y.push_back(run.rows[i].measured.at(key));
    const auto sd = run.rows[i].measured_sd.find(key);
    experiment.err.push_back(sd == run.rows[i].measured_sd.end() ? 0.0 : sd->second);
  }
  p.series = {ours};
  if (!photographed.x.empty()) p.series.push_back(photographed);
  p.series.push_back(experiment);
  return p;
}
}  // namespace

std::vector<PlotSpec> sand_gun_plots(const SandGunRun& run) {
  if (sand_gun_speed_series(run).empty()) return {};
  // The ejecta as the photographs could see them, unless the run already counts them so.
  std::vector<std::map<std::string, MeanInterval>> seen(run.rows.size());
  if (run.visible_above != kPhotographsSeeAbove)
    for (std::size_t i : sand_gun_speed_series(run))
      seen[i] = sand_gun_quantities(run.impacts[i], kPhotographsSeeAbove, 2 * run.bed.spec.radius);
  return {figure(run, seen, "ejecta", "sand_gun_ejecta.png", "Ejecta per event (Table 3.12)",
                 "ejecta per event", true),
          figure(run, seen, "ej_vz", "sand_gun_ejection_speed.png", "Ejection vertical velocity (Table 3.12)",
                 "v_ey (cm/s)", true),
          figure(run, seen, "reptation", "sand_gun_reptation.png", "Reptation per ejectum (Table 3.12)",
                 "2 v_x v_z / g (cm)", true),
          figure(run, seen, "theta_i", "sand_gun_rebound.png", "Rebound angle from the vertical (Table 3.11)",
                 "theta_i (deg)", false)};
}

}  // namespace grainlab::validation
