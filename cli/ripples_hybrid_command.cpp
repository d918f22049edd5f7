// `grainlab ripples hybrid-flux`: the 3-D hybrid model's saturated flux over a fixed flat bed, and
// `grainlab ripples hybrid --config FILE`: its ripple runs over an erodible bed, streamed to HDF5/XDMF
// (issue #17, ripples/hybrid/, docs/ripples.md "3-D hybrid model").
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "hybrid_config.hpp"
#include "input_error.hpp"
#include "progress.hpp"
#include "ripple_config.hpp"
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

namespace grainlab::cli {

namespace {

using ripples::hybrid::BedFrame;

const std::vector<std::string> kHistoryColumns = {
    "t_star", "amplitude",      "wavelength", "ripple_index", "mean_height",
    "shift",  "mass_flux_star", "airborne",   "u_star_bed",   "loosening"};

std::vector<double> history_row(const BedFrame& f) {
  return {f.t_star, f.stats.amplitude, f.stats.wavelength, f.stats.ripple_index, f.stats.mean,
          f.shift,  f.mass_flux_star,  f.airborne,         f.u_star_bed,         f.loosening};
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

}  // namespace

int hybrid_ripples_command(const RipplesCommands& a) {
  if (a.config.empty()) throw InputError({"--config", 0}, "", "give a [hybrid] config (docs/ripples.md)");
  refuse_existing_out(a.out, a.force);
  const std::string text = ripples::read_config_text(a.config);
  ripples::hybrid::HybridConfig config = ripples::hybrid::parse_hybrid_config(text, a.config);
  ripples::hybrid::RippleOptions& o = config.options;
  if (a.duration_override > 0)
    o.duration = a.duration_override, o.frame_every = std::min(o.frame_every, o.duration);
  ripples::hybrid::RippleRun run(o);
  const auto& bed = run.bed();
  const double dx = bed.cell() / o.diameter;
  std::unique_ptr<GridSeriesWriter> out;
  if (!a.out.empty())
    out = std::make_unique<GridSeriesWriter>(a.out, a.force, bed.nx(), bed.ny(), dx, "height");
  const bool talk = !a.quiet && !a.json;
  if (talk)
    fmt::print(
        "hybrid ripples: {} d x {} d ({} x {} key points, {} d apart), s = {:.0f}, Ga = {:.1f}, S = {:.4f}, "
        "u* = {} cm/s, splash {}\n",
        o.length, o.width, bed.nx(), bed.ny(), dx, run.transport().density_ratio(), run.transport().galileo(),
        run.transport().shields(), o.u_star, o.splash);
  ProgressBar bar(talk, "t*");
  std::vector<BedFrame> frames;
  auto take = [&] {
    frames.push_back(run.frame());
    const BedFrame& f = frames.back();
    if (out) out->add_frame(f.t_star, f.h);
    frames.back().h.clear();  // streamed; the statistics stay
  };
  take();
  const auto start = std::chrono::steady_clock::now();
  for (double t = o.frame_every; t <= o.duration * (1 + 1e-12); t += o.frame_every) {
    run.advance_to(t, [&](double now) { bar.update(now, o.duration); });
    take();
    if (run.transport().airborne() == 0) break;  // transport died
  }
  bar.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const ripples::hybrid::RippleTrends trend = ripples::hybrid::ripple_trends(frames);
  const BedFrame& last = frames.back();
  if (out) {
    SampleTable history{
        "history",
        "per frame: t* = t / sqrt(d / g^); amplitude 2 sqrt(2 C(0)), wavelength (first peak of the "
        "slice-averaged autocorrelation), ripple index, mean height, downwind shift since the "
        "previous frame (grain diameters); Q* and grains airborne averaged since the previous "
        "frame; u* at the bed (cm/s); E_eff / E_d2",
        kHistoryColumns,
        {}};
    for (const BedFrame& f : frames) history.rows.push_back(history_row(f));
    SampleTable flux{
        "flux", "flux samples: t*, Q*, grains airborne", {"t_star", "mass_flux_star", "airborne"}, {}};
    for (const auto& s : run.series()) flux.rows.push_back({s[0], s[1], s[2]});
    const std::string xmf = out->commit(
        {history, flux}, {{"grainlab_version", GRAINLAB_VERSION},
                          {"model", "3-D hybrid ripple model, Huo et al. 2021 (grainlab ripples hybrid)"},
                          {"config", config.text},
                          {"units",
                           "frames: bed height in grain diameters above the initial surface, x and y in "
                           "grain diameters (x downwind); time t* = t / sqrt(d / g^)"},
                          {"dx", fmt::format("{:.17g}", dx)},
                          {"time_unit", "t*"}});
    if (talk) fmt::print("wrote {} and {}\n", a.out, xmf);
  }
  const auto& tr = run.transport();
  const double rate = wall > 0 ? static_cast<double>(tr.grain_steps) / wall : 0;
  if (a.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (const BedFrame& f : frames) rows.push_back(history_row(f));
    const nlohmann::json j{{"t_star", last.t_star},
                           {"amplitude", last.stats.amplitude},
                           {"wavelength", last.stats.wavelength},
                           {"ripple_index", last.stats.ripple_index},
                           {"mass_flux_star", last.mass_flux_star},
                           {"growth_rate", number_or_null(trend.growth_rate)},
                           {"chi", number_or_null(trend.chi)},
                           {"migration_speed", number_or_null(trend.migration_speed)},
                           {"s", tr.density_ratio()},
                           {"galileo", tr.galileo()},
                           {"shields", tr.shields()},
                           {"splash", o.splash},
                           {"deposited", bed.deposited},
                           {"eroded", bed.eroded},
                           {"grain_steps", tr.grain_steps},
                           {"grain_steps_per_second", rate},
                           {"wall_seconds", wall},
                           {"history_columns", kHistoryColumns},
                           {"history", rows}};
    fmt::print("{}\n", j.dump());
    return 0;
  }
  fmt::print(
      "t* = {:.0f}: A = {:.3g} d, lambda = {:.3g} d, RI = {:.3g}; Q* = {:.4g} ({:.0f} grains airborne)\n",
      last.t_star, last.stats.amplitude, last.stats.wavelength, last.stats.ripple_index, last.mass_flux_star,
      last.airborne);
  fmt::print(
      "  growth rate of A {:.3g} per t* (first half), chi = {:.3g} (second half), migration {:.3g} d per "
      "t*\n",
      trend.growth_rate, trend.chi, trend.migration_speed);
  fmt::print("  {} grain-steps in {:.1f} s: {:.3g} grain-steps/s\n", tr.grain_steps, wall, rate);
  return 0;
}

}  // namespace grainlab::cli
