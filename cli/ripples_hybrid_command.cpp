// `grainlab ripples hybrid-flux`: the 3-D hybrid model's saturated flux over a fixed flat bed (issue #17,
// ripples/hybrid/flux_model.hpp, docs/ripples.md "3-D hybrid model").
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "input_error.hpp"
#include "progress.hpp"
#include "ripples_commands.hpp"

namespace grainlab::cli {

int hybrid_flux_command(const RipplesCommands& a) {
  const ripples::hybrid::FluxOptions& o = a.flux;
  if (!(o.average_from < o.duration))
    throw InputError({"--average-from", 0}, fmt::format("{}", o.average_from),
                     fmt::format("must be before the end of the run (--duration {})", o.duration));
  ripples::hybrid::FluxOptions run = o;
  ProgressBar bar(!a.quiet && !a.json);
  run.progress = [&](double t, double total) { bar.update(t, total); };
  const ripples::hybrid::FluxResult r = ripples::hybrid::run_flux(run);
  bar.finish();
  const double rate = r.wall_seconds > 0 ? static_cast<double>(r.grain_steps) / r.wall_seconds : 0;
  if (a.json) {
    nlohmann::json series = nlohmann::json::array();
    for (const auto& row : r.series) series.push_back(row);
    const nlohmann::json j{{"u_star", o.u_star},
                           {"s", r.s},
                           {"galileo", r.galileo},
                           {"shields", r.shields},
                           {"mass_flux", r.mass_flux},
                           {"mass_flux_star", r.mass_flux_star},
                           {"mass_flux_sd", r.mass_flux_sd},
                           {"airborne", r.airborne},
                           {"u_star_bed", r.u_star_bed},
                           {"impact_speed", r.mean_impact_speed},
                           {"impact_angle_deg", r.mean_impact_angle_deg},
                           {"collisions", r.collisions},
                           {"splash", o.splash},
                           {"wind_loosened", o.wind_loosened},
                           {"grain_steps", r.grain_steps},
                           {"steps", r.steps},
                           {"grain_steps_per_second", rate},
                           {"wall_seconds", r.wall_seconds},
                           {"series", series}};
    fmt::print("{}\n", j.dump());
    return 0;
  }
  fmt::print("hybrid flux: s = {:.0f}, Ga = {:.1f}, S = {:.4f} (u* = {} cm/s, splash {})\n", r.s, r.galileo,
             r.shields, o.u_star, o.splash);
  fmt::print(
      "  Q = {:.4g} g/(cm s) (sd {:.3g}), Q* = {:.4g}; {:.0f} grains airborne; u* at the bed {:.2f} cm/s\n",
      r.mass_flux, r.mass_flux_sd, r.mass_flux_star, r.airborne, r.u_star_bed);
  fmt::print("  impacts {:.1f} cm/s at {:.1f} deg; {} mid-air collisions\n", r.mean_impact_speed,
             r.mean_impact_angle_deg, r.collisions);
  fmt::print("  {} grain-steps in {:.1f} s: {:.3g} grain-steps/s\n", r.grain_steps, r.wall_seconds, rate);
  return 0;
}

}  // namespace grainlab::cli
