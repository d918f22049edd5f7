// `grainlab ripples hybrid-flux`: the 3-D hybrid model's saturated flux over a fixed flat bed, and
// `grainlab ripples hybrid --config FILE`: its ripple runs over an erodible bed, streamed to HDF5/XDMF
// (issue #17, ripples/hybrid/, docs/hybrid.md "The 3-D hybrid model").
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "frame_tables.hpp"
#include "h5_input.hpp"
#include "h5_output.hpp"
#include "hybrid_config.hpp"
#include "hybrid_splash_file.hpp"
#include "input_error.hpp"
#include "option_scope.hpp"
#include "parallel.hpp"
#include "plot_beside.hpp"
#include "progress.hpp"
#include "ripple_config.hpp"
#include "ripples_commands.hpp"

namespace grainlab::cli {

namespace {
// A distributed run gives each rank at least one block of the collision grid's columns.
void refuse_too_many_ranks(const ripples::hybrid::TransportOptions& o, const std::string& where,
                           const std::string& key) {
  const long most = ripples::hybrid::max_ranks(o);
  if (parallel::size() > most)
    throw InputError({where, 0}, key,
                     fmt::format("a domain {} d long splits over at most {} MPI ranks (each takes whole "
                                 "blocks of columns at least 2 d wide), not {}",
                                 o.length, most, parallel::size()));
}
}  // namespace

constexpr const char* kFluxCheckpointKind = "grainlab-hybrid-flux-checkpoint/1";

// What a continued flux run must match: every option that changes its bits, all but the duration (a run
// may be taken further) and the checkpoints' own.
std::string flux_fingerprint(const ripples::hybrid::FluxOptions& o) {
  return fmt::format(
      "u_star {:.17g}, diameter {:.17g}, grain_density {:.17g}, fluid_density {:.17g}, viscosity {:.17g}, "
      "length {:.17g}, width {:.17g}, average_from {:.17g}, splash {}, collisions {}, wind_loosened {}, "
      "dead_rise {:.17g}, swept {}, fast_substeps {}, travel {:.17g}, dt_max {:.17g}, seed {}, "
      "collide_within_splash {}",
      o.u_star, o.diameter, o.grain_density, o.fluid_density, o.viscosity, o.length, o.width, o.average_from,
      o.splash, o.collisions, o.wind_loosened, o.dead_rise, o.swept, o.fast_substeps, o.travel, o.dt_max,
      o.seed, o.collide_within_splash);
}

void check_flux_options(const ripples::hybrid::FluxOptions& o) {
  if (!(o.average_from < o.duration))
    throw InputError({"--average-from", 0}, fmt::format("{}", o.average_from),
                     fmt::format("must be before the end of the run (--duration {})", o.duration));
  if (o.travel > 0.5 && !o.swept)
    throw InputError({"--travel", 0}, fmt::format("{}", o.travel),
                     "above 0.5 d grains can pass through each other unseen: add --swept");
  if (o.fast_substeps && !o.swept)
    throw InputError({"--fast-substeps", 0}, "", "needs --swept: fast grains are found along their paths");
}

ripples::hybrid::FluxResult run_flux_checkpointed(ripples::hybrid::FluxOptions run,
                                                  const ripples::hybrid::FluxOptions& o,
                                                  const std::string& checkpoint, const std::string& restart) {
  const std::string fingerprint = flux_fingerprint(o);
  if (!checkpoint.empty())
    run.checkpoint = [checkpoint, fingerprint](const std::vector<SampleTable>& tables) {
      if (parallel::rank() == 0)
        write_sample_tables(checkpoint, tables,
                            {{"kind", kFluxCheckpointKind},
                             {"grainlab_version", GRAINLAB_VERSION},
                             {"options", fingerprint}});
    };
  std::map<std::string, SampleTable> state;
  if (!restart.empty()) {
    const TableFile file = read_sample_tables(restart, ripples::hybrid::flux_checkpoint_columns(run));
    require_checkpoint(file, restart, kFluxCheckpointKind, "hybrid flux checkpoint", fingerprint,
                       "was written with other options: give the same ones (only --duration may change)");
    state = file.tables, run.restart = &state;
  }
  try {
    return ripples::hybrid::run_flux(run);
  } catch (const std::invalid_argument& e) {
    if (restart.empty()) throw;
    throw InputError({restart, 0}, "--restart", e.what());  // (the checkpoint did not fit)
  }
}

int hybrid_flux_command(const RipplesCommands& a) {
  const ripples::hybrid::FluxOptions& o = a.flux;
  check_flux_options(o);
  check_stop_at(a.stop_at, a.hybrid_checkpoint, o.duration, fmt::format("t* = {:g}", o.duration));
  ripples::hybrid::FluxOptions run = o;
  validation::attach_recorded_splash(run);
  run.distributed = parallel::size() > 1;  // the ranks share the domain; the first one reports
  refuse_too_many_ranks(run, "--length", "");
  // (The bar is on stderr, so it stays with --json: a scripted run of hours still shows in its log.)
  ProgressBar bar(!a.quiet && parallel::rank() == 0);
  run.progress = [&](double t, double total) { bar.update(t, total); };
  run.stop_at = a.stop_at;
  const ripples::hybrid::FluxResult r = run_flux_checkpointed(run, o, a.hybrid_checkpoint, a.hybrid_restart);
  bar.finish();
  if (parallel::rank() != 0) return 0;
  if (r.stopped) {
    fmt::print(stderr, "stopped at t* = {:.0f}; continue with --restart {}\n", r.t_star, a.hybrid_checkpoint);
    return 0;
  }
  const double rate = r.wall_seconds > 0 ? static_cast<double>(r.grain_steps) / r.wall_seconds : 0;
  // A window with no impact holds only the seeded grains' first flights: say so rather than let Q pass
  // for saltation (on stderr, so --json stays one object).
  if (r.impacts_per_area_time == 0)
    fmt::print(
        stderr,
        "grainlab ripples hybrid-flux: note: no grain hit the bed between t* = {:g} and {:g}: Q is the "
        "seeded grains' first flights, not a saturated flux; run longer (--duration, --average-from)\n",
        o.average_from, o.duration);
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
                           {"airborne_mass_star", r.airborne_mass_star},
                           {"u_star_bed", r.u_star_bed},
                           {"impact_speed", r.mean_impact_speed},
                           {"impact_angle_deg", r.mean_impact_angle_deg},
                           {"bed_friction", r.bed_friction},
                           {"collisions", r.collisions},
                           {"collide_within_splash", o.collide_within_splash},
                           {"splash", o.splash},
                           {"wind_loosened", o.wind_loosened},
                           {"swept", o.swept},
                           {"fast_substeps", o.fast_substeps},
                           {"fast_collisions", r.fast_collisions},
                           {"travel", o.travel},
                           {"dt_max", o.dt_max},
                           {"grain_steps", r.grain_steps},
                           {"steps", r.steps},
                           {"grain_steps_per_second", rate},  // all ranks together
                           {"ranks", parallel::size()},
                           {"wall_seconds", r.wall_seconds},
                           {"t_star", r.t_star},
                           {"series", series},
                           {"wind", {{"z", r.z}, {"u", r.u_mean}, {"u_end", r.u}, {"u_clean", r.u_clean}}}};
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
  fmt::print("  {} grain-steps in {:.1f} s: {:.3g} grain-steps/s{}\n", r.grain_steps, r.wall_seconds, rate,
             parallel::size() > 1 ? fmt::format(" on {} MPI ranks", parallel::size()) : "");
  return 0;
}

}  // namespace grainlab::cli

namespace grainlab::cli {

namespace {

using ripples::hybrid::BedFrame;

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

// A bed of several sizes: each frame's mean surface grain size by column (d), as rows t*, x0, x1, ...
SampleTable size_profiles(const std::vector<BedFrame>& frames, std::size_t nx) {
  SampleTable t{"surface_size",
                "per frame: t*, then the surface layer's mean grain size (d) of each key-point column "
                "averaged across the bed (coarse crests are the armouring of bidisperse ripples)",
                {"t_star"},
                {}};
  for (std::size_t i = 0; i < nx; ++i) t.columns.push_back(fmt::format("x{}", i));
  for (const BedFrame& f : frames) {
    if (f.size_profile.size() != nx) continue;  // (every frame has one, restored frames too; a guard)
    std::vector<double> row{f.t_star};
    row.insert(row.end(), f.size_profile.begin(), f.size_profile.end());
    t.rows.push_back(row);
  }
  return t;
}

constexpr const char* kCheckpointKind = "grainlab-hybrid-ripples-checkpoint/1";

// What a continued run must match: the config's values as the run reads them (not its comments or
// layout). The duration it runs to is kept beside them, but a run may be continued to another one
// (`--duration`, or the config's own), since where a run stops changes nothing before.
constexpr const char* kDurationMark = "\n# duration ";
std::string fingerprint(const ripples::hybrid::HybridConfig& c) {
  return fmt::format("{}{}{:.17g}", c.values, kDurationMark, c.options.duration);
}

// The checkpoint's fingerprint if it is this config's with another duration (any duration passes; the
// frames it holds are checked against the new one after reading), else this run's own, which it then
// fails to match. Checkpoints written before 2026-12-05 hold the config's whole text instead of its
// values, and continue under that text alone.
std::string continued_fingerprint(const TableFile& file, const ripples::hybrid::HybridConfig& c) {
  const auto it = file.metadata.find("options");
  if (it == file.metadata.end()) return fingerprint(c);
  const std::string& theirs = it->second;
  const auto at = theirs.rfind(kDurationMark);
  auto same = [&](const std::string& ours) { return at == ours.size() && theirs.compare(0, at, ours) == 0; };
  return at != std::string::npos && (same(c.values) || same(c.text)) ? theirs : fingerprint(c);
}

// The run's state, the frames taken so far (their statistics and profiles) and, when the bed history is
// being written, every frame's heights, so a continued run rewrites the same file.
void write_hybrid_checkpoint(const std::string& path, const ripples::hybrid::HybridConfig& c,
                             const ripples::hybrid::RippleRun& run, const std::vector<BedFrame>& frames,
                             const std::vector<std::vector<double>>& written) {
  std::vector<SampleTable> tables = run.save("run/");  // collective: every rank's grains
  if (parallel::rank() != 0) return;
  const std::size_t nx = run.bed().nx();
  for (SampleTable& t : ripples::hybrid::frame_tables(frames, nx, !c.options.sizes.empty(), "cli/"))
    tables.push_back(std::move(t));
  std::vector<double> height_values;
  for (const auto& h : written) height_values.insert(height_values.end(), h.begin(), h.end());
  tables.push_back(ripples::hybrid::grid_table(
      "cli/frames", "every written frame's heights (d), frame after frame", height_values, nx));
  write_sample_tables(
      path, tables,
      {{"kind", kCheckpointKind}, {"grainlab_version", GRAINLAB_VERSION}, {"options", fingerprint(c)}});
}

void read_hybrid_checkpoint(const std::string& path, const ripples::hybrid::HybridConfig& c,
                            ripples::hybrid::RippleRun& run, std::vector<BedFrame>& frames,
                            std::vector<std::vector<double>>& written, std::size_t cells) {
  const bool sizes = !c.options.sizes.empty();
  std::map<std::string, std::vector<std::string>> wanted = ripples::hybrid::frame_table_names(sizes, "cli/");
  wanted["cli/frames"] = {};
  for (const SampleTable& t : run.save("run/")) wanted[t.name] = t.columns;  // the tables a run writes
  // The config first (a bed of other sizes has other tables), then the tables.
  const TableFile meta = read_sample_tables(path, {});
  const std::string expected = continued_fingerprint(meta, c);
  std::string differences;
  if (const auto it = meta.metadata.find("options"); it != meta.metadata.end() && it->second != expected)
    differences =
        ripples::hybrid::config_differences(it->second.substr(0, it->second.rfind(kDurationMark)), c);
  require_checkpoint(meta, path, kCheckpointKind, "hybrid ripple checkpoint", expected,
                     "was written for another config: pass the one it was started with, and the same --set "
                     "overrides (comments and layout may differ, values not" +
                         (differences.empty() ? std::string(")") : "; " + differences + ")"));
  const TableFile file = read_sample_tables(path, wanted);
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--restart", why); };
  try {
    run.restore(file.tables, "run/");
    frames = ripples::hybrid::frames_of_tables(file.tables, run.bed().nx(),
                                               run.bed().cell() / c.options.diameter, sizes, "cli/");
    // Frames are taken at frame_times (each within a step after its time). A run whose duration is not a
    // whole number of intervals took its last frame at its end, off the grid another duration continues on.
    // A frame is taken within a step (at most dt_max, 0.02 t* by default) after its time: 1 t* is ample,
    // and far less than a frame interval. (It was a tenth of the interval: a run that ended at t* = 600,
    // continued to 640 with frames every 1000, passed as having taken its frame at 640 and ran no step.)
    const double every = c.options.frame_every, last = frames.back().t_star;
    const double slack = std::min(0.1 * every, 1.0);
    if (last > c.options.duration + slack)
      refuse(
          fmt::format("is at t* = {:.0f}, past the duration asked for ({:g}): give a --duration of at "
                      "least that",
                      last, c.options.duration));
    const std::vector<double> times = ripples::hybrid::frame_times(c.options.duration, every);
    if (frames.size() > times.size() || std::abs(last - times[frames.size() - 1]) > slack)
      refuse(
          fmt::format("has its last frame at t* = {:.0f}, off this run's frames (one every {:g} t*, and "
                      "one at the end): a run that ended between two frames cannot be continued",
                      last, every));
    const std::vector<double> h = ripples::hybrid::grid_values(
        ripples::hybrid::checkpoint_table(file.tables, "cli/frames", run.bed().nx()));
    if (h.size() % cells != 0) refuse("has a bed history of the wrong size");
    for (std::size_t k = 0; k < h.size(); k += cells)
      written.emplace_back(h.begin() + static_cast<long>(k), h.begin() + static_cast<long>(k + cells));
  } catch (const std::invalid_argument& e) {
    refuse(e.what());
  }
}

// The run file's tables and metadata beside the frames already streamed into it, and its plot.
void write_hybrid_output(GridSeriesWriter& out, const RipplesCommands& a,
                         const ripples::hybrid::HybridConfig& config, const ripples::hybrid::RippleRun& run,
                         const std::vector<BedFrame>& frames, const ripples::hybrid::RippleTrends& trend,
                         const std::vector<ripples::hybrid::ImpactRecord>& impact_log, bool talk) {
  const ripples::hybrid::RippleOptions& o = config.options;
  const auto& bed = run.bed();
  const double dx = bed.cell() / o.diameter;
  SampleTable history{
      "history",
      "per frame: t* = t / sqrt(d / g^); amplitude 2 sqrt(2 C(0)), wavelength (first peak of the "
      "slice-averaged autocorrelation), ripple index, mean height, downwind shift since the "
      "previous frame (grain diameters); Q* and grains airborne averaged since the previous "
      "frame; u* at the bed (cm/s); E_eff / E_d2; the surface grain size at crests and troughs (d); z0 "
      "of the log layer (d); the stoss and lee angles (deg); mid-air collisions per t* per 1,000 d^2 "
      "of bed since the previous frame; the crests' mean spacing and height (d) and their ratio, slice "
      "by slice",
      ripples::hybrid::frame_history_columns(),
      {}};
  for (const BedFrame& f : frames) history.rows.push_back(ripples::hybrid::frame_history_row(f));
  SampleTable flux{
      "flux", "flux samples: t*, Q*, grains airborne", {"t_star", "mass_flux_star", "airborne"}, {}};
  for (const auto& s : run.series()) flux.rows.push_back({s[0], s[1], s[2]});
  SampleTable response{"bed_response",
                       "the bed's linear response by wavelength band over the frames: growth rate (per t*, "
                       "with its standard error) and downwind phase speed (d per t*); wavelengths in d",
                       {"lambda_min", "lambda_max", "growth_rate", "growth_error", "phase_speed"},
                       {}};
  for (const auto& b : trend.response)
    response.rows.push_back({b.lambda_min, b.lambda_max, b.growth_rate, b.growth_error, b.phase_speed});
  std::vector<SampleTable> tables{history, flux, response};
  if (!o.sizes.empty()) tables.push_back(size_profiles(frames, bed.nx()));
  if (a.impacts_from >= 0)
    tables.push_back(
        ripples::hybrid::impact_table(impact_log, a.impacts_from, run.transport().time_unit(), o.diameter));
  const std::string xmf = out.commit(
      tables, {{"grainlab_version", GRAINLAB_VERSION},
               {"model", "3-D hybrid ripple model, Huo et al. 2021 (grainlab ripples hybrid)"},
               {"config", config.text},
               {"wind", !o.wind_follows_bed ? "column on the mean bed level"
                        : o.wind_relief_fades
                            ? "column on the bed's relief as it fades with height in potential flow "
                              "(wind_relief_fades)"
                            : "column on the bed beneath each grain (wind_follows_bed)"},
               {"units",
                "frames: bed height in grain diameters above the initial surface, x and y in "
                "grain diameters (x downwind); time t* = t / sqrt(d / g^)"},
               {"dx", fmt::format("{:.17g}", dx)},
               {"sizes", fmt::format("{} (diameters), fractions {}", nlohmann::json(o.sizes).dump(),
                                     nlohmann::json(o.fractions).dump())},
               {"time_unit", "t*"}});
  if (talk) fmt::print("wrote {} and {}\n", a.out, xmf);
  draw_plot_beside(a.out, "_ripples", "plot_hybrid.py", {a.out}, a.force, a.json,
                   "the bed, the space-time plot, A, lambda, RI, Q* and the flank slopes");
}

// `--json`: the last frame, the fits, the run's settings and its whole history.
nlohmann::json hybrid_json(const ripples::hybrid::RippleOptions& o, const ripples::hybrid::RippleRun& run,
                           const std::vector<BedFrame>& frames, const ripples::hybrid::RippleTrends& trend,
                           double rate, double wall, std::uint64_t collisions) {
  const BedFrame& last = frames.back();
  const auto& tr = run.transport();
  const auto& bed = run.bed();
  nlohmann::json rows = nlohmann::json::array();
  for (const BedFrame& f : frames) {
    nlohmann::json row = nlohmann::json::array();
    for (double v : ripples::hybrid::frame_history_row(f)) row.push_back(number_or_null(v));
    rows.push_back(row);
  }
  nlohmann::json response = nlohmann::json::array();
  for (const auto& b : trend.response)
    response.push_back({{"lambda_min", b.lambda_min},
                        {"lambda_max", b.lambda_max},
                        {"growth_rate", b.growth_rate},
                        {"phase_speed", b.phase_speed},
                        {"growth_error", number_or_null(b.growth_error)}});
  return nlohmann::json{{"t_star", last.t_star},
                        {"u_star", o.u_star},
                        {"seed", o.seed},
                        {"length", o.length},
                        {"width", o.width},
                        {"amplitude", last.stats.amplitude},
                        {"wavelength", last.stats.wavelength},
                        {"ripple_index", last.stats.ripple_index},
                        {"ripple_index_5e4_3e5", number_or_null(trend.window_ripple_index)},
                        {"ripple_index_5e4_3e5_frames", trend.window_frames},
                        {"crest_spacing", number_or_null(last.stats.crest_spacing)},
                        {"crest_height", number_or_null(last.stats.crest_height)},
                        {"crest_ripple_index", number_or_null(last.stats.crest_ripple_index)},
                        {"crest_ripple_index_5e4_3e5", number_or_null(trend.window_crest_ripple_index)},
                        {"stoss_deg", number_or_null(last.stats.stoss_deg)},
                        {"lee_deg", number_or_null(last.stats.lee_deg)},
                        {"mass_flux_star", last.mass_flux_star},
                        {"growth_rate", number_or_null(trend.growth_rate)},
                        {"chi", number_or_null(trend.chi)},
                        {"migration_speed", number_or_null(trend.migration_speed)},
                        {"bed_response", response},
                        {"s", tr.density_ratio()},
                        {"galileo", tr.galileo()},
                        {"shields", tr.shields()},
                        {"splash", o.splash},
                        {"wind_follows_bed", o.wind_follows_bed},
                        {"wind_relief_fades", o.wind_relief_fades},
                        {"wind_loosened", o.wind_loosened},
                        {"ejecta_launch", o.ejecta_vertical ? "vertical" : "normal"},
                        {"splash_frame", o.splash_level ? "level" : "facet"},
                        {"cell", o.cell},
                        {"repose_deg", o.repose_deg},
                        {"key_point_repose_deg", key_point_repose_deg(o)},
                        {"swept", o.swept},
                        {"fast_substeps", o.fast_substeps},
                        {"fast_collisions", tr.fast_collisions},
                        {"collisions", collisions},
                        {"steps", tr.steps},
                        {"travel", o.travel},
                        {"dt_max", o.dt_max},
                        {"sizes", o.sizes},
                        {"fractions", o.fractions},
                        {"size_crest", number_or_null(last.size_crest)},
                        {"size_trough", number_or_null(last.size_trough)},
                        {"deposited", bed.deposited},
                        {"eroded", bed.eroded},
                        {"grain_steps", tr.grain_steps},
                        {"grain_steps_per_second", rate},  // all ranks together
                        {"ranks", parallel::size()},
                        {"wall_seconds", wall},
                        {"history_columns", ripples::hybrid::frame_history_columns()},
                        {"history", rows}};
}

// The summary for people: the last frame, the fits, the bed's response by band, the speed.
void print_hybrid_summary(const ripples::hybrid::RippleOptions& o, const ripples::hybrid::RippleRun& run,
                          const BedFrame& last, const ripples::hybrid::RippleTrends& trend, double rate,
                          double wall) {
  const auto& tr = run.transport();
  fmt::print(
      "t* = {:.0f}: A = {:.3g} d, lambda = {:.3g} d, RI = {:.3g}, flanks {:.3g} deg stoss / {:.3g} deg lee; "
      "Q* = {:.4g} ({:.0f} grains airborne)\n",
      last.t_star, last.stats.amplitude, last.stats.wavelength, last.stats.ripple_index, last.stats.stoss_deg,
      last.stats.lee_deg, last.mass_flux_star, last.airborne);
  // A fit the frames do not allow (a run too short for ripples) is NaN: said in words, not printed as "nan".
  using ripples::hybrid::shown_fit;
  const bool unfitted =
      !std::isfinite(trend.growth_rate) || !std::isfinite(trend.chi) || !std::isfinite(trend.migration_speed);
  fmt::print("  growth rate of A {} per t* (first half), chi = {} (second half), migration {} d per t*{}\n",
             shown_fit(trend.growth_rate), shown_fit(trend.chi), shown_fit(trend.migration_speed),
             unfitted ? " (n/a: too few frames with ripples to fit)" : "");
  fmt::print("  crests: {:.3g} d apart, {:.3g} d high, RI {:.3g} (slice by slice)\n",
             last.stats.crest_spacing, last.stats.crest_height, last.stats.crest_ripple_index);
  if (trend.window_frames > 0)
    fmt::print(
        "  mean RI over t* = 5e4-3e5 (the paper's Fig. 9 inset): {:.3g} ({} frames); the crests' RI: "
        "{}\n",
        trend.window_ripple_index, trend.window_frames, shown_fit(trend.window_crest_ripple_index));
  fmt::print(
      "  key points {} d apart: a settling grain rolls on past steps steeper than {:.1f} deg (repose {} deg "
      "less its own rise over a cell)\n",
      o.cell, key_point_repose_deg(o), o.repose_deg);
  if (!trend.response.empty()) {
    fmt::print(
        "  the bed's response by wavelength band (growth rate per t*, downwind phase speed d per t*):\n");
    for (const auto& b : trend.response)
      fmt::print("    {:7.1f}-{:7.1f} d: {:+.2e} +- {:.1e} per t*, {:+.2e} d per t*{}\n", b.lambda_min,
                 b.lambda_max, b.growth_rate, b.growth_error, b.phase_speed,
                 b.growth_rate > 2 * b.growth_error ? "  (growing)" : "");
  }
  fmt::print("  {} grain-steps in {:.1f} s: {:.3g} grain-steps/s{}\n", tr.grain_steps, wall, rate,
             parallel::size() > 1 ? fmt::format(" on {} MPI ranks", parallel::size()) : "");
}

// The run's config from --config, --set and --duration, refusing what cannot run.
ripples::hybrid::HybridConfig hybrid_config(const RipplesCommands& a) {
  if (a.config.empty()) throw InputError({"--config", 0}, "", "give a [hybrid] config (docs/hybrid.md)");
  refuse_existing_out(a.out, a.force);
  if (a.impacts_from >= 0 && a.out.empty())
    throw InputError({"--impacts-from", 0}, fmt::format("{}", a.impacts_from), "needs --out to log into");
  const std::string text = ripples::read_config_text(a.config);
  ripples::hybrid::HybridConfig config = ripples::hybrid::parse_hybrid_config(text, a.config, a.overrides);
  ripples::hybrid::RippleOptions& o = config.options;
  if (a.duration_override > 0)
    o.duration = a.duration_override, o.frame_every = std::min(o.frame_every, o.duration);
  check_stop_at(a.stop_at, a.hybrid_checkpoint, o.duration, fmt::format("t* = {:g}", o.duration));
  validation::attach_recorded_splash(o);
  // Under mpirun the ranks share the domain (bit for bit the results of one process); the first one
  // writes and reports.
  o.distributed = parallel::size() > 1;
  refuse_too_many_ranks(o, a.config, "length");
  return config;
}

// The frames taken so far: their statistics, each one's heights streamed to --out as it is taken, and
// kept too when checkpoints must hold them.
struct FrameKeeper {
  std::unique_ptr<GridSeriesWriter> out;
  bool keep = false;
  std::vector<BedFrame> frames;
  std::vector<std::vector<double>> written;  // the frames' heights, kept only for checkpoints

  void take(ripples::hybrid::RippleRun& run) {
    frames.push_back(run.frame());
    const BedFrame& f = frames.back();
    if (out) out->add_frame(f.t_star, f.h);
    if (keep) written.push_back(f.h);
    frames.back().h.clear();  // streamed; the statistics stay
  }

  // The frames of the run a checkpoint continues, written again to --out.
  void restore(const std::string& path, const ripples::hybrid::HybridConfig& config,
               ripples::hybrid::RippleRun& run, std::size_t points) {
    read_hybrid_checkpoint(path, config, run, frames, written, points);
    if (out)
      for (std::size_t k = 0; k < written.size(); ++k) out->add_frame(frames[k].t_star, written[k]);
    if (!keep) written.clear();
  }
};

void print_hybrid_header(const ripples::hybrid::RippleOptions& o, const ripples::hybrid::RippleRun& run) {
  const auto& bed = run.bed();
  fmt::print(
      "hybrid ripples: {} d x {} d ({} x {} key points, {} d apart), s = {:.0f}, Ga = {:.1f}, S = {:.4f}, "
      "u* = {} cm/s, splash {}\n",
      o.length, o.width, bed.nx(), bed.ny(), bed.cell() / o.diameter, run.transport().density_ratio(),
      run.transport().galileo(), run.transport().shields(), o.u_star, o.splash);
}

}  // namespace

int hybrid_ripples_command(const RipplesCommands& a) {
  const ripples::hybrid::HybridConfig config = hybrid_config(a);
  const ripples::hybrid::RippleOptions& o = config.options;
  const bool first = parallel::rank() == 0;
  ripples::hybrid::RippleRun run(o);
  const auto& bed = run.bed();
  FrameKeeper kept;
  if (!a.out.empty() && first)
    kept.out = std::make_unique<GridSeriesWriter>(a.out, a.force, bed.nx(), bed.ny(), bed.cell() / o.diameter,
                                                  "height");
  kept.keep = kept.out && !a.hybrid_checkpoint.empty();
  const bool talk = !a.quiet && !a.json && first;
  if (talk) print_hybrid_header(o, run);
  ProgressBar bar(!a.quiet && first, "t*");  // (stderr: kept with --json, as above)
  if (!a.hybrid_restart.empty()) {
    kept.restore(a.hybrid_restart, config, run, bed.nx() * bed.ny());
    if (talk) fmt::print("continuing from t* = {:.0f} ({})\n", kept.frames.back().t_star, a.hybrid_restart);
  }
  if (kept.frames.empty()) kept.take(run);
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t steps_before = run.transport().grain_steps;
  const std::vector<double> times = ripples::hybrid::frame_times(o.duration, o.frame_every);
  double next_checkpoint =
      (std::floor(kept.frames.back().t_star / a.checkpoint_every + 1e-9) + 1) * a.checkpoint_every;
  // The impact log (the first rank's: every rank does every splash), from the frame interval that reaches
  // --impacts-from; a continued run logs only what it runs itself.
  std::vector<ripples::hybrid::ImpactRecord> impact_log;
  for (std::size_t k = kept.frames.size(); k < times.size(); ++k) {
    const double t = times[k];
    if (kept.out && a.impacts_from >= 0 && t > a.impacts_from) run.log_impacts(&impact_log);
    run.advance_to(t, [&](double now) {
      bar.update(now, o.duration, fmt::format("{} grains airborne", run.transport().airborne()));
    });
    kept.take(run);
    const bool stop = a.stop_at > 0 && t >= a.stop_at * (1 - 1e-12), end = k + 1 == times.size();
    // (And at the end, so that a finished run can be taken further with --restart and a longer --duration.)
    if (!a.hybrid_checkpoint.empty() && (t >= next_checkpoint * (1 - 1e-12) || stop || end)) {
      write_hybrid_checkpoint(a.hybrid_checkpoint, config, run, kept.frames, kept.written);
      next_checkpoint += a.checkpoint_every;
    }
    if (stop) {
      bar.finish();
      if (!first) return 0;
      fmt::print(stderr, "stopped at t* = {:.0f}; continue with --restart {}\n", t, a.hybrid_checkpoint);
      return 0;  // the output stays unwritten: the continued run writes it whole
    }
    if (run.transport().airborne() == 0) break;  // transport died
  }
  bar.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const ripples::hybrid::RippleTrends trend = ripples::hybrid::ripple_trends(kept.frames);
  if (kept.out) write_hybrid_output(*kept.out, a, config, run, kept.frames, trend, impact_log, talk);
  const auto& tr = run.transport();
  const double rate = wall > 0 ? static_cast<double>(tr.grain_steps - steps_before) / wall : 0;
  const std::uint64_t collisions = tr.total_collisions();  // (a sum over the ranks: every rank takes part)
  if (!first) return 0;
  if (a.json) {
    fmt::print("{}\n", hybrid_json(o, run, kept.frames, trend, rate, wall, collisions).dump());
    return 0;
  }
  print_hybrid_summary(o, run, kept.frames.back(), trend, rate, wall);
  return 0;
}

}  // namespace grainlab::cli
