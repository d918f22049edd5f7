#include "flux_model.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "transport.hpp"

namespace grainlab::ripples::hybrid {

CleanWind clean_wind(const FluxOptions& o) {
  check_transport_options(o);
  const WindColumn wind({o.u_star, o.viscosity, o.fluid_density, o.diameter, o.height * o.diameter});
  return {wind.z(), wind.clean()};
}

double flux_law(double shields, double shields_threshold, double kappa, double mu_b, double c_m) {
  const double excess = std::max(0.0, shields - shields_threshold);
  return 2 * std::sqrt(shields_threshold) / (kappa * mu_b) * excess * (1 + c_m / mu_b * excess);
}

FluxResult run_flux(const FluxOptions& o) {
  check_transport_options(o);
  if (!(o.duration > 0) || !(o.average_from < o.duration))
    throw std::invalid_argument("the duration must be positive and average_from before the end");
  const auto start = std::chrono::steady_clock::now();
  Transport run(o, nullptr);
  FluxResult r;
  r.s = run.density_ratio(), r.galileo = run.galileo(), r.shields = run.shields();
  const double t_unit = run.time_unit(), t_end = o.duration * t_unit, t_avg = o.average_from * t_unit;
  double next_sample = 0, q_sum = 0, q_sum2 = 0, air_sum = 0, window_start = -1;
  std::size_t samples = 0;
  while (run.time() < t_end) {
    run.step();
    const bool in_window = run.time() >= t_avg;
    if (in_window && window_start < 0) run.tally = {}, window_start = run.time();
    if (run.time() >= next_sample) {
      const double q = run.mass_flux();
      r.series.push_back({run.time() / t_unit, q / run.flux_unit(), static_cast<double>(run.airborne())});
      if (in_window) q_sum += q, q_sum2 += q * q, air_sum += static_cast<double>(run.airborne()), ++samples;
      if (o.progress) o.progress(run.time() / t_unit, o.duration);
      next_sample += t_unit;
    }
    if (run.airborne() == 0) break;  // transport died
  }
  if (samples > 0) {
    const double n = static_cast<double>(samples);
    r.mass_flux = q_sum / n, r.airborne = air_sum / n;
    r.mass_flux_sd = std::sqrt(std::max(0.0, q_sum2 / n - r.mass_flux * r.mass_flux));
    r.mass_flux_star = r.mass_flux / run.flux_unit();
  }
  if (run.tally.impacts > 0 && window_start >= 0) {
    r.mean_impact_speed = run.tally.speed_sum / run.tally.impacts;
    r.mean_impact_angle_deg = run.tally.angle_sum / run.tally.impacts * 180 / M_PI;
    const double area = o.length * o.width * o.diameter * o.diameter;
    r.impacts_per_area_time = run.tally.impacts / (area * std::max(run.time() - window_start, 1e-300));
    r.bed_friction = run.tally.bed_pz > 0 ? run.tally.bed_px / run.tally.bed_pz : 0;
  }
  r.grain_steps = run.grain_steps, r.steps = run.steps, r.collisions = run.total_collisions();
  r.fast_collisions = run.fast_collisions;
  r.u_star_bed = std::sqrt(run.wind().bed_stress());
  r.z = run.wind().z(), r.u = run.wind().u(), r.u_clean = run.wind().clean();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace grainlab::ripples::hybrid
