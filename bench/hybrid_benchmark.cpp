#include "hybrid_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "flux_model.hpp"

namespace grainlab::bench {

namespace {

struct Rate {
  double grain_steps_per_second = 0, t_star_per_second = 0, airborne = 0, grain_steps_per_t_star = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Medians over `repeats` runs of each variant, the variants taken in turn within each repeat so that a
// shared machine's slow spells fall on all of them (each run's own wall clock, set-up included).
std::vector<Rate> median_rates(const std::vector<ripples::hybrid::FluxOptions>& variants, int repeats) {
  std::vector<std::vector<double>> rates(variants.size()), t_rates(variants.size());
  std::vector<Rate> out(variants.size());
  for (int k = 0; k < repeats; ++k)
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const ripples::hybrid::FluxResult r = ripples::hybrid::run_flux(variants[v]);
      rates[v].push_back(static_cast<double>(r.grain_steps) / r.wall_seconds);
      t_rates[v].push_back(variants[v].duration / r.wall_seconds);
      out[v].airborne = r.airborne;
      out[v].grain_steps_per_t_star = static_cast<double>(r.grain_steps) / variants[v].duration;
    }
  for (std::size_t v = 0; v < variants.size(); ++v)
    out[v].grain_steps_per_second = median(rates[v]), out[v].t_star_per_second = median(t_rates[v]);
  return out;
}

}  // namespace

int run_hybrid_bench(const HybridBenchOptions& o) {
  ripples::hybrid::FluxOptions f;
  f.length = o.length, f.width = o.width, f.u_star = o.u_star, f.duration = o.duration;
  f.average_from = 0.5 * o.duration;
  ripples::hybrid::FluxOptions free = f, swept = f;
  free.collisions = false;
  swept.swept = true, swept.travel = 1.5;
  const std::vector<Rate> r = median_rates({f, free, swept}, o.repeats);
  const Rate &full = r[0], &without = r[1], &long_steps = r[2];
  // What the swept steps give per t*, as the grain-steps per second the paper's steps would need to
  // keep up: swept t* per second times the paper's grain-steps per t*.
  const double equivalent = long_steps.t_star_per_second * full.grain_steps_per_t_star;
  // Memory: per airborne grain six doubles of state, an 8-byte id, an 8-byte splash number, a 1-byte size
  // class, and three 4-byte indices in the collision grid (chain link, column x and y); per one-diameter
  // column of the grid (length x width / d^2 of them) a 4-byte chain head and an occupancy bit. Swept steps
  // add a 4-byte slot per grain (and 28 bytes for each grain that collided in the step: its shift) and use
  // columns (1 + 4/3 travel) x (1 + 2/3 travel) = 3 d x 2 d wide.
  const double per_grain = 6 * 8 + 8 + 8 + 1 + 3 * 4, per_column = 4 + 1.0 / 8;
  fmt::print(
      "hybrid model, {} d x {} d, u* = {} cm/s, {} t*, median of {}: {:.3g} grain-steps/s ({:.0f} grains "
      "airborne, {:.3g} t*/s); without mid-air collisions {:.3g} grain-steps/s (collisions cost {:.0f} %); "
      "memory {:.0f} bytes per airborne grain + {:.2f} per d^2 of bed\n",
      o.length, o.width, o.u_star, o.duration, o.repeats, full.grain_steps_per_second, full.airborne,
      full.t_star_per_second, without.grain_steps_per_second,
      100 * (without.grain_steps_per_second / full.grain_steps_per_second - 1), per_grain, per_column);
  fmt::print(
      "swept steps (travel 1.5 d): {:.3g} grain-steps/s, {:.3g} t*/s ({:.2f}x the 0.2 d steps' t*/s, "
      "{:.1f}x fewer grain-steps per t*): as fast as {:.3g} grain-steps/s of 0.2 d steps\n",
      long_steps.grain_steps_per_second, long_steps.t_star_per_second,
      long_steps.t_star_per_second / full.t_star_per_second,
      full.grain_steps_per_t_star / long_steps.grain_steps_per_t_star, equivalent);
  if (!o.json.empty())
    std::ofstream(o.json)
        << nlohmann::json{{"length_d", o.length},
                          {"width_d", o.width},
                          {"u_star", o.u_star},
                          {"duration_t_star", o.duration},
                          {"repeats", o.repeats},
                          {"grain_steps_per_second", full.grain_steps_per_second},
                          {"t_star_per_second", full.t_star_per_second},
                          {"grain_steps_per_second_without_collisions", without.grain_steps_per_second},
                          {"swept_grain_steps_per_second", long_steps.grain_steps_per_second},
                          {"swept_t_star_per_second", long_steps.t_star_per_second},
                          {"swept_equivalent_grain_steps_per_second", equivalent},
                          {"airborne", full.airborne},
                          {"bytes_per_grain", per_grain}}
               .dump(2)
        << "\n";
  return 0;
}

}  // namespace grainlab::bench
