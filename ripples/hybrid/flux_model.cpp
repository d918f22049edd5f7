#include "flux_model.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include "fluid.hpp"
#include "transport.hpp"

namespace grainlab::ripples::hybrid {

CleanWind clean_wind(const FluxOptions& o) {
  check_transport_options(o);
  const WindColumn wind({o.u_star, o.viscosity, o.fluid_density, o.diameter, o.height * o.diameter});
  return {wind.z(), wind.clean()};
}

double flux_law_mass(double shields, double shields_threshold, double mu_b) {
  return fluid::transport_law_mass(shields, shields_threshold, mu_b);
}

double flux_law_velocity(double shields, double shields_threshold, double kappa, double mu_b, double c_m) {
  return fluid::transport_law_velocity(shields, shields_threshold, kappa, mu_b, c_m);
}

double flux_law(double shields, double shields_threshold, double kappa, double mu_b, double c_m) {
  return flux_law_mass(shields, shields_threshold, mu_b) *
         flux_law_velocity(shields, shields_threshold, kappa, mu_b, c_m);
}

namespace {

// The flux run's own state beside its transport's: the sampling clock, the window's sums and the samples.
struct FluxState {
  double next_sample = 0, q_sum = 0, q_sum2 = 0, air_sum = 0, window_start = -1, samples = 0, wall = 0;
  std::vector<std::array<double, 3>> series;
  std::vector<double> u_sum;  // the wind at each mesh node, summed over the window's samples (cm/s)
};

const std::vector<std::string> kFluxStateColumns = {"next_sample",     "q_sum",       "q_sum2", "air_sum",
                                                    "window_start",    "samples",     "bed_px", "bed_pz",
                                                    "fast_collisions", "wall_seconds"};
const std::vector<std::string> kSeriesColumns = {"t_star", "mass_flux_star", "airborne"};
const std::vector<std::string> kWindColumns = {"u_sum"};

std::vector<SampleTable> save_flux(const Transport& run, const FluxState& f, double wall) {
  std::vector<SampleTable> tables = run.save("run/");  // (collective: every rank's grains)
  tables.push_back({"flux/state",
                    "the sampling clock (s), the window's sums (g/(cm s), their squares, grains), where it "
                    "began (s; -1 not yet), the samples in it, the bed's momentum tally, the fast pass's "
                    "collisions and the wall time so far",
                    kFluxStateColumns,
                    {{f.next_sample, f.q_sum, f.q_sum2, f.air_sum, f.window_start, f.samples,
                      run.tally.bed_px, run.tally.bed_pz, static_cast<double>(run.fast_collisions), wall}}});
  SampleTable series{"flux/series", "flux samples: t*, Q*, grains airborne", kSeriesColumns, {}};
  for (const auto& row : f.series) series.rows.push_back({row[0], row[1], row[2]});
  tables.push_back(series);
  SampleTable wind{
      "flux/wind", "the wind at each mesh node summed over the window's samples (cm/s)", kWindColumns, {}};
  for (double u : f.u_sum) wind.rows.push_back({u});
  tables.push_back(wind);
  return tables;
}

FluxState restore_flux(Transport& run, const std::map<std::string, SampleTable>& tables) {
  run.restore(tables, "run/");
  const SampleTable& state = checkpoint_table(tables, "flux/state", kFluxStateColumns.size());
  if (state.rows.size() != 1) throw std::invalid_argument("the checkpoint's flux state is not one row");
  const std::vector<double>& v = state.rows[0];
  FluxState f{v[0], v[1], v[2], v[3], v[4], v[5], v[9], {}, {}};
  run.tally.bed_px = v[6], run.tally.bed_pz = v[7];
  run.fast_collisions = static_cast<std::uint64_t>(v[8]);
  for (const auto& row : checkpoint_table(tables, "flux/series", kSeriesColumns.size()).rows)
    f.series.push_back({row[0], row[1], row[2]});
  for (const auto& row : checkpoint_table(tables, "flux/wind", kWindColumns.size()).rows)
    f.u_sum.push_back(row[0]);
  if (f.u_sum.size() != run.wind().u().size())
    throw std::invalid_argument("the checkpoint's window wind has the wrong number of mesh nodes");
  return f;
}

}  // namespace

std::map<std::string, std::vector<std::string>> flux_checkpoint_columns(const FluxOptions& o) {
  check_transport_options(o);
  std::map<std::string, std::vector<std::string>> columns{
      {"flux/state", kFluxStateColumns}, {"flux/series", kSeriesColumns}, {"flux/wind", kWindColumns}};
  FluxOptions local = o;
  local.distributed = false;  // (only the names: no collective)
  for (const SampleTable& t : Transport(local, nullptr).save("run/")) columns[t.name] = t.columns;
  return columns;
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
  FluxState f;
  f.u_sum.assign(run.wind().u().size(), 0.0);
  if (o.restart) f = restore_flux(run, *o.restart);
  // A run continued from the checkpoint written at its own end (within a t* past the duration: the
  // step that crossed it) is finished, and its result is read from that state: so a study of several runs
  // (hybrid-focal) continues without redoing the ones it had.
  const bool finished = o.restart && run.time() >= t_end && run.time() < t_end + t_unit;
  if (run.time() >= t_end && !finished)
    throw std::invalid_argument(fmt::format("the checkpoint is at t* = {:.0f}, not before the duration {:g}",
                                            run.time() / t_unit, o.duration));
  auto wall = [&] {
    return f.wall + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double every = o.checkpoint_every;
  double next_checkpoint = every > 0 ? (std::floor(run.time() / t_unit / every + 1e-9) + 1) * every : 0;
  while (run.time() < t_end) {
    run.step();
    const bool in_window = run.time() >= t_avg;
    if (in_window && f.window_start < 0) run.tally = {}, f.window_start = run.time();
    const bool sampled = run.time() >= f.next_sample;
    if (sampled) {
      const double q = run.mass_flux();
      f.series.push_back({run.time() / t_unit, q / run.flux_unit(), static_cast<double>(run.airborne())});
      if (in_window) {
        f.q_sum += q, f.q_sum2 += q * q, f.air_sum += static_cast<double>(run.airborne()), ++f.samples;
        const std::vector<double>& u = run.wind().u();
        for (std::size_t k = 0; k < u.size(); ++k) f.u_sum[k] += u[k];
      }
      if (o.progress) o.progress(run.time() / t_unit, o.duration);
      f.next_sample += t_unit;
    }
    const bool died = run.airborne() == 0, end = run.time() >= t_end || died;
    const bool stop = sampled && o.stop_at > 0 && run.time() >= o.stop_at * t_unit && !end;
    // Checkpoints fall on samples (and at the end, so that a finished run can be taken further).
    const bool due = every > 0 && sampled && run.time() / t_unit >= next_checkpoint * (1 - 1e-12);
    if (o.checkpoint && (due || stop || end)) {
      o.checkpoint(save_flux(run, f, wall()));
      while (every > 0 && next_checkpoint <= run.time() / t_unit) next_checkpoint += every;
    }
    if (stop) {
      r.stopped = true;
      break;
    }
    if (died) break;  // transport died
  }
  r.series = f.series;
  if (f.samples > 0) {
    const double n = f.samples;
    r.mass_flux = f.q_sum / n, r.airborne = f.air_sum / n;
    r.mass_flux_sd = std::sqrt(std::max(0.0, f.q_sum2 / n - r.mass_flux * r.mass_flux));
    r.mass_flux_star = r.mass_flux / run.flux_unit();
    r.airborne_mass_star = r.airborne * M_PI / (6 * o.length * o.width);  // grains of diameter d on L W d^2
    for (double u : f.u_sum) r.u_mean.push_back(u / n);
  }
  if (run.tally.impacts > 0 && f.window_start >= 0) {
    r.mean_impact_speed = run.tally.speed_sum / run.tally.impacts;
    r.mean_impact_angle_deg = run.tally.angle_sum / run.tally.impacts * 180 / M_PI;
    const double area = o.length * o.width * o.diameter * o.diameter;
    r.impacts_per_area_time = run.tally.impacts / (area * std::max(run.time() - f.window_start, 1e-300));
    r.bed_friction = run.tally.bed_pz > 0 ? run.tally.bed_px / run.tally.bed_pz : 0;
  }
  r.grain_steps = run.grain_steps, r.steps = run.steps, r.collisions = run.total_collisions();
  r.fast_collisions = run.fast_collisions;
  r.u_star_bed = std::sqrt(run.wind().bed_stress());
  r.z = run.wind().z(), r.u = run.wind().u(), r.u_clean = run.wind().clean();
  r.t_star = run.time() / t_unit;
  r.wall_seconds = wall();
  return r;
}

}  // namespace grainlab::ripples::hybrid
