// `grainlab saltation dem`: saltation from first principles, a periodic DEM bed under a wind with grain
// feedback (issue #18, docs/saltation.md "DEM saltation").
#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "dem_saltation.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "option_scope.hpp"
#include "parallel.hpp"
#include "progress.hpp"
#include "report.hpp"
#include "saltation_commands.hpp"

namespace grainlab::cli {

namespace fs = std::filesystem;
using validation::MeanInterval;

namespace {

nlohmann::json interval_json(const MeanInterval& m) {
  return {{"mean", m.mean}, {"sd", m.sd}, {"lo", m.lo}, {"hi", m.hi}, {"n", m.n}};
}

nlohmann::json splash_json(const saltation::SplashFile& f) {
  nlohmann::json cells = nlohmann::json::array();
  for (const saltation::SplashCell& c : f.cells) {
    nlohmann::json j{{"speed_sqrt_gd", c.speed}, {"angle_deg", c.angle_deg}, {"impacts", c.impacts}};
    for (const auto& [name, m] : c.moments) j[name] = m.mean;
    cells.push_back(j);
  }
  return cells;
}

nlohmann::json result_json(const validation::DemSaltationOptions& o,
                           const validation::DemSaltationResult& r) {
  return {{"u_star", o.u_star},
          {"mass_flux", r.mass_flux.mean},
          {"mass_flux_interval", interval_json(r.mass_flux)},
          {"mass_flux_halves", {r.first_half_flux, r.second_half_flux}},
          {"u_star_eff", r.u_star_eff.mean},
          {"airborne", r.airborne.mean},
          {"transport_velocity", r.transport_velocity},
          {"mean_hop_height", r.hop_height.mean},
          {"mean_hop_length", r.hop_length.mean},
          {"hops", r.hop_height.n},
          {"impact_speed", interval_json(r.impact_speed)},
          {"impact_angle", interval_json(r.impact_angle)},
          {"liftoff_speed", interval_json(r.liftoff_speed)},
          {"liftoff_angle", interval_json(r.liftoff_angle)},
          {"impacts", r.impacts.size()},
          {"liftoffs", r.liftoffs.size()},
          {"saltons",
           {{"hop_height", r.salton_hop_height.mean},
            {"hop_length", r.salton_hop_length.mean},
            {"hops", r.salton_hop_height.n},
            {"impact_speed", interval_json(r.salton_impact_speed)},
            {"impact_angle", interval_json(r.salton_impact_angle)}}},
          {"steady_model_with_this_splash",
           {{"ran", r.model.ran},
            {"converged", r.model.converged},
            {"failure", r.model.failure},
            {"mass_flux", r.model.mass_flux},
            {"u_star_eff", r.model.u_star_eff},
            {"mean_hop_height", r.model.hop_height},
            {"mean_hop_length", r.model.hop_length}}},
          {"momentum",
           {{"wind_loss", r.wind_momentum_loss},
            {"grain_gain", r.grain_momentum_gain},
            {"stress_partition", r.stress_partition},
            {"coupling_lag", r.coupling_lag}}},
          {"splash", splash_json(r.splash)},
          {"grains", r.grains},
          {"bed_width_cm", r.bed_width},
          {"slab_thickness_cm", r.slab_thickness},
          {"dt", r.dt},
          {"k_n", o.k_n},
          {"duration", o.duration},
          {"average_from", o.average_from},
          {"steps", r.steps},
          {"wall_seconds", r.wall_seconds},
          {"wind_share", r.wall_seconds > 0 ? r.wind_seconds / r.wall_seconds : 0.0},
          {"ranks", parallel::size()}};
}

std::string profiles_csv(const validation::DemSaltationResult& r) {
  std::string csv =
      "z_cm,concentration_g_cm3,flux_density_g_cm2_s,wind_cm_s,wind_clean_cm_s,grain_stress_dyn_cm2\n";
  for (std::size_t k = 0; k < r.z.size(); ++k)
    csv += fmt::format("{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", r.z[k], r.concentration[k],
                       r.flux_density[k], r.wind[k], r.wind_clean[k], r.grain_stress[k]);
  return csv;
}

std::vector<validation::PlotSpec> dem_plots(const validation::DemSaltationResult& r) {
  using validation::PlotSpec;
  PlotSpec series{"dem_flux_time.png", "Mass flux over time", "t (s)", "Q (g/(cm s))", false, {}};
  PlotSpec::Series q{"Q", "line", {}, {}, {}};
  for (const auto& row : r.series) q.x.push_back(row[0]), q.y.push_back(row[1]);
  series.series.push_back(q);
  PlotSpec wind{"dem_wind.png", "Wind over the bed: with grains and clean", "u (cm/s)", "z (cm)", false, {}};
  PlotSpec conc{"dem_concentration.png", "Grain mass concentration", "z (cm)", "c (g/cm^3)", false, {}};
  conc.logy = true;
  PlotSpec::Series w{"with grains", "line", {}, {}, {}}, c{"clean", "dashed", {}, {}, {}},
      m{"concentration", "line", {}, {}, {}};
  for (std::size_t k = 0; k < r.z.size(); ++k) {
    if (r.z[k] <= 0) continue;
    w.x.push_back(r.wind[k]), w.y.push_back(r.z[k]);
    c.x.push_back(r.wind_clean[k]), c.y.push_back(r.z[k]);
    if (r.concentration[k] > 0) m.x.push_back(r.z[k]), m.y.push_back(r.concentration[k]);
  }
  wind.series = {w, c};
  wind.logy = true;
  conc.series = {m};
  return {series, wind, conc};
}

}  // namespace

int dem_command(const SaltationCommands& a) {
  validation::DemSaltationOptions o = a.dem;
  if (!(o.average_from < o.duration))
    throw InputError({"--average-from", 0}, fmt::format("{}", o.average_from),
                     fmt::format("must be before the end of the run (--duration {})", o.duration));
  check_stop_at(o.stop_at, o.checkpoint, o.duration, fmt::format("--duration {}", o.duration));
  if (!a.dem_out.empty() && fs::exists(a.dem_out) && !a.force)
    throw InputError({"--out", 0}, a.dem_out, "exists; pass --force to replace it");
  o.distributed = parallel::size() > 1;
  const bool root = parallel::rank() == 0;
  ProgressBar bar(!a.quiet && root);
  o.progress = [&](double t, double total) { bar.update(t, total); };
  const validation::DemSaltationResult r = validation::run_dem_saltation(o);
  bar.finish();
  if (!root) return 0;
  if (r.stopped) {
    fmt::print(stderr, "stopped at t = {} s; continue with --restart {}\n", o.stop_at, o.checkpoint);
    return 0;
  }
  const nlohmann::json j = result_json(o, r);
  if (!a.dem_out.empty()) {
    const std::string tmp = a.dem_out + ".partial";
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    nlohmann::json meta = j;
    meta["grainlab_version"] = GRAINLAB_VERSION;
    meta["scene"] = validation::dem_saltation_scene(o);
    write_file_atomically(tmp + "/dem_saltation.json", meta.dump(2));
    write_file_atomically(tmp + "/profiles.csv", profiles_csv(r));
    std::string ts = "t_s,mass_flux_g_cm_s,u_star_eff_cm_s,airborne\n";
    for (const auto& row : r.series)
      ts += fmt::format("{:.6g},{:.6g},{:.6g},{:.0f}\n", row[0], row[1], row[2], row[3]);
    write_file_atomically(tmp + "/series.csv", ts);
    // The impact and lift-off velocity distributions: every crossing of one diameter above the bed.
    for (const auto& [name, list] : {std::pair{"impacts", &r.impacts}, std::pair{"liftoffs", &r.liftoffs}}) {
      std::string csv = "t_s,x_cm,vx_cm_s,vy_cm_s,grain\n";
      for (const validation::Crossing& x : *list)
        csv += fmt::format("{:.6f},{:.5f},{:.4f},{:.4f},{}\n", x.t, x.x, x.vx, x.vy, x.grain);
      write_file_atomically(tmp + "/" + name + ".csv", csv);
    }
    if (!r.splash.cells.empty()) saltation::write_splash_file(tmp + "/splash.h5", r.splash, true);
    validation::write_plots(dem_plots(r), tmp);
    fs::remove_all(a.dem_out);
    fs::rename(tmp, a.dem_out);
  }
  if (a.dem_json) {
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("DEM saltation: {} grains, bed {:.2f} cm wide, u* = {} cm/s, {} steps in {:.3g} s ({} ranks)\n",
             r.grains, r.bed_width, o.u_star, r.steps, r.wall_seconds, parallel::size());
  fmt::print("  mass flux {:.4g} g/(cm s) [{:.4g}, {:.4g}] (halves {:.4g} / {:.4g}); u*_eff {:.2f} cm/s\n",
             r.mass_flux.mean, r.mass_flux.lo, r.mass_flux.hi, r.first_half_flux, r.second_half_flux,
             r.u_star_eff.mean);
  fmt::print("  {:.0f} grains airborne; {} hops: height {:.3f} cm, length {:.2f} cm\n", r.airborne.mean,
             r.hop_height.n, r.hop_height.mean, r.hop_length.mean);
  fmt::print("  impacts {}: speed {:.1f} cm/s at {:.1f} deg; lift-offs {}: {:.1f} cm/s at {:.1f} deg\n",
             r.impacts.size(), r.impact_speed.mean, r.impact_angle.mean, r.liftoffs.size(),
             r.liftoff_speed.mean, r.liftoff_angle.mean);
  fmt::print(
      "  momentum per bed area: wind lost {:.4g}, grains got {:.4g} dyn/cm^2 (lag per interval {:.3g}); "
      "tau_f + tau_g = {:.3f} rho u*^2\n",
      r.wind_momentum_loss, r.grain_momentum_gain, r.coupling_lag, r.stress_partition);
  fmt::print("  grains above 1 d move downwind at {:.1f} cm/s on average (their flux / their mass)\n",
             r.transport_velocity);
  if (r.salton_hop_height.n == 0)
    fmt::print("  saltation hops (> 5 d): none in the averaging window\n");
  else
    fmt::print(
        "  saltation hops (> 5 d) {}: height {:.3f} cm, length {:.2f} cm, impact {:.1f} cm/s at {:.1f} deg\n",
        r.salton_hop_height.n, r.salton_hop_height.mean, r.salton_hop_length.mean, r.salton_impact_speed.mean,
        r.salton_impact_angle.mean);
  if (r.model.ran)
    fmt::print("  Ch. IV model with this splash: {} Q {:.4g} g/(cm s), u*_eff {:.2f} cm/s, hop {:.3f} cm\n",
               r.model.converged ? "converged," : "NOT converged (" + r.model.failure + "),",
               r.model.mass_flux, r.model.u_star_eff, r.model.hop_height);
  fmt::print("  wind drag and updates: {:.1f} % of the run\n", 100 * r.wind_seconds / r.wall_seconds);
  if (!a.dem_out.empty())
    fmt::print(
        "  wrote {}/ (dem_saltation.json, profiles.csv, series.csv, impacts.csv, liftoffs.csv, splash.h5, "
        "plots)\n",
        a.dem_out);
  return 0;
}

}  // namespace grainlab::cli
