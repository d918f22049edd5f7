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
  double grain_steps_per_second = 0, airborne = 0;
};

// Median over `repeats` runs of grain-steps per second (the run's own wall clock, set-up included).
Rate median_rate(const ripples::hybrid::FluxOptions& f, int repeats) {
  std::vector<double> rates;
  double airborne = 0;
  for (int k = 0; k < repeats; ++k) {
    const ripples::hybrid::FluxResult r = ripples::hybrid::run_flux(f);
    rates.push_back(static_cast<double>(r.grain_steps) / r.wall_seconds);
    airborne = r.airborne;
  }
  std::sort(rates.begin(), rates.end());
  return {rates[rates.size() / 2], airborne};
}

}  // namespace

int run_hybrid_bench(const HybridBenchOptions& o) {
  ripples::hybrid::FluxOptions f;
  f.length = o.length, f.width = o.width, f.u_star = o.u_star, f.duration = o.duration;
  f.average_from = 0.5 * o.duration;
  const Rate full = median_rate(f, o.repeats);
  f.collisions = false;
  const Rate free = median_rate(f, o.repeats);
  // Memory: six doubles and an 8-byte id per airborne grain, two 4-byte indices (chain and column) in
  // the collision grid, and one 4-byte chain head per column of the grid (length x width / d^2 of them).
  const double per_grain = 6 * 8 + 8 + 2 * 4 + 1, per_column = 4;  // state, id; chain; size class
  fmt::print(
      "hybrid model, {} d x {} d, u* = {} cm/s, {} t*, median of {}: {:.3g} grain-steps/s ({:.0f} grains "
      "airborne); without mid-air collisions {:.3g} grain-steps/s (collisions cost {:.0f} %); memory {:.0f} "
      "bytes per airborne grain + {:.0f} per d^2 of bed\n",
      o.length, o.width, o.u_star, o.duration, o.repeats, full.grain_steps_per_second, full.airborne,
      free.grain_steps_per_second, 100 * (free.grain_steps_per_second / full.grain_steps_per_second - 1),
      per_grain, per_column);
  if (!o.json.empty())
    std::ofstream(o.json) << nlohmann::json{{"length_d", o.length},
                                            {"width_d", o.width},
                                            {"u_star", o.u_star},
                                            {"duration_t_star", o.duration},
                                            {"repeats", o.repeats},
                                            {"grain_steps_per_second", full.grain_steps_per_second},
                                            {"grain_steps_per_second_without_collisions",
                                             free.grain_steps_per_second},
                                            {"airborne", full.airborne},
                                            {"bytes_per_grain", per_grain}}
                                 .dump(2)
                          << "\n";
  return 0;
}

}  // namespace grainlab::bench
