#include "ripples_commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "bin_model.hpp"
#include "ensemble.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "lammel_splash.hpp"
#include "number_ranges.hpp"
#include "output_path.hpp"
#include "plot_beside.hpp"
#include "ripple_config.hpp"
#include "triangles.hpp"
#include "worms.hpp"

namespace grainlab::cli {

namespace {

using namespace grainlab::ripples;

// Whether a model's option sets the run: always without a config; with one, where it was given on the
// command line (it then replaces the config's value).
bool sets_run(const RipplesCommands& a, const CLI::App* command, const char* name) {
  return a.config.empty() || command->count(name) > 0;
}

int chain_command(const RipplesCommands& a) {
  if (a.start < 0 || a.start > a.links)
    throw InputError({"--start", 0}, std::to_string(a.start),
                     fmt::format("must lie in 0..{} (--links)", a.links));
  const WormChainResult r = worm_chain(a.links, a.start, a.A, a.steps);
  const std::size_t merged = worm_pair_merges(a.links, a.start, a.A, a.steps, a.runs, a.seed);
  const validation::Proportion w = validation::wilson_interval(merged, a.runs);
  const double lo = w.lo, hi = w.hi;
  const double mc = double(merged) / double(a.runs);
  if (a.json) {
    fmt::print("{}\n",
               nlohmann::json{{"absorbed", r.absorbed},
                              {"links", a.links},
                              {"start", a.start},
                              {"A", a.A},
                              {"steps", a.steps},
                              {"mean_links_moved", r.mean_links_moved},
                              {"monte_carlo", {{"runs", a.runs}, {"merged", mc}, {"lo", lo}, {"hi", hi}}}}
                   .dump(2));
    return 0;
  }
  fmt::print(
      "two worms of {} links in all, one starting at {}, A = {}, {} steps (each worm advances A/l per "
      "step)\n",
      a.links, a.start, a.A, a.steps);
  fmt::print(
      "  exact (the chain's matrix): merged with probability {:.5f}; the first worm moved {:.1f} links\n",
      r.absorbed, r.mean_links_moved);
  fmt::print("  Monte Carlo of the rule ({} runs): {:.5f}, 95 % interval [{:.5f}, {:.5f}]\n", a.runs, mc, lo,
             hi);
  return 0;
}

}  // namespace

void refuse_existing_out(const std::string& out, bool force) {
  if (!out.empty() && !force && std::filesystem::exists(out))
    throw InputError({"--out", 0}, out, "exists; pass --force to overwrite it");
}

void write_spacetime_plot(const std::string& h5, bool force, bool json) {
  draw_plot_beside(h5, "_spacetime", "plot_ripples.py", {h5}, force, json, "the space-time plot");
}

namespace {

int ring_command(const RipplesCommands& a) {
  refuse_existing_out(a.out, a.force);
  WormRingRun run;
  if (!a.config.empty()) run = parse_worm_ring_config(read_config_text(a.config), a.config);
  auto given = [&](const char* name) { return sets_run(a, a.ring, name); };
  if (given("--worms")) run.worms = a.worms;
  if (given("--length")) run.length = a.length;
  if (given("--A")) run.A = a.A;
  if (given("--steps")) run.steps = a.ring_steps;
  if (given("--seed")) run.seed = a.seed;
  // (A config's values were checked where it was read.)
  if (run.worms < 2) throw InputError({"--worms", 0}, std::to_string(run.worms), "needs at least 2 worms");
  if (run.length < 1) throw InputError({"--length", 0}, std::to_string(run.length), "needs at least 1 link");
  const WormRingResult r = worm_ring(run.worms, run.length, run.A, run.steps, run.seed, run.records);
  std::vector<int> sorted = r.lengths;
  std::sort(sorted.begin(), sorted.end());
  const double mean = r.mean_length.empty() ? run.length : r.mean_length.back();
  if (!a.out.empty()) {
    SampleTable history{"history", "per record: step, mean worm length (links)", {"step", "mean_length"}, {}};
    for (std::size_t k = 0; k < r.mean_length.size(); ++k)
      history.rows.push_back({double(r.recorded_steps[k]), r.mean_length[k]});
    SampleTable lengths{"lengths", "the surviving worms' lengths (links), in ring order", {"length"}, {}};
    for (int l : r.lengths) lengths.rows.push_back({double(l)});
    write_sample_tables(a.out, {history, lengths},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", "Haff's worm model (thesis Fig. 5.16)"},
                         {"config", run.text.empty() ? "(command-line options)" : run.text}});
  }
  if (a.json) {
    fmt::print("{}\n", nlohmann::json{{"worms", r.lengths.size()},
                                      {"mean_length", mean},
                                      {"lengths", r.lengths},
                                      {"steps", r.recorded_steps},
                                      {"mean_length_history", r.mean_length}}
                           .dump(2));
    return 0;
  }
  fmt::print(
      "{} worms of {} links on a ring, A = {}, {} steps: {} worms left, mean length {:.2f} (median {}, "
      "longest {})\n",
      run.worms, run.length, run.A, run.steps, r.lengths.size(), mean, sorted[sorted.size() / 2],
      sorted.back());
  return 0;
}

int triangles_command(const RipplesCommands& a) {
  refuse_existing_out(a.out, a.force);
  TriangleRun run;
  if (!a.config.empty()) run = parse_triangle_config(read_config_text(a.config), a.config);
  auto given = [&](const char* name) { return sets_run(a, a.triangles, name); };
  if (given("--ratio")) {
    run.ratio = a.ratio;
  }
  if (given("--law")) run.params.law = a.law;
  if (given("--beta")) run.params.beta_deg = a.beta;
  if (given("--alpha")) run.params.alpha_deg = a.alpha;
  const TriangleParams& p = run.params;
  if (!(p.beta_deg > 0 && p.alpha_deg > 0 && p.beta_deg + p.alpha_deg < 90))
    throw InputError({"--beta", 0}, fmt::format("{}, {}", p.beta_deg, p.alpha_deg),
                     "slopes must be positive and sum below 90 deg");
  const CollisionResult r = triangle_collision(p, run.ratio);
  if (!a.out.empty()) {
    SampleTable history{"history",
                        "during the collision: time (H_D0^2 / q0), upstream and downstream heights and the "
                        "intercept y_i (units of the downstream ripple's initial height)",
                        {"t", "h_up", "h_down", "y_i"},
                        {}};
    for (std::size_t k = 0; k < r.t.size(); ++k)
      history.rows.push_back({r.t[k], r.h_up[k], r.h_down[k], r.y_i[k]});
    write_sample_tables(a.out, {history},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", "the thesis's triangular collision model (Figs 5.17-5.20)"},
                         {"config", run.text.empty() ? "(command-line options)" : run.text}});
  }
  const double ratio = run.ratio;
  if (a.json) {
    fmt::print("{}\n", nlohmann::json{{"law", p.law},
                                      {"ratio", ratio},
                                      {"upstream_after", r.upstream_after},
                                      {"downstream_after", r.downstream_after},
                                      {"min_effective_height", r.min_effective_height},
                                      {"area_before", r.area_before},
                                      {"area_after", r.area_after},
                                      {"contact_time", r.duration}}
                           .dump(2));
    return 0;
  }
  fmt::print(
      "triangular ripples (stoss {} deg, lee {} deg), {} transport: upstream {} x the downstream height\n",
      p.beta_deg, p.alpha_deg, p.law, ratio);
  fmt::print(
      "  after the collision: upstream {:.4f}, downstream {:.4f} (heights / the downstream's initial)\n",
      r.upstream_after, r.downstream_after);
  fmt::print(
      "  smallest effective upstream height during it: {:.4f} of its free height; sand {:.6f} -> {:.6f}\n",
      r.min_effective_height, r.area_before, r.area_after);
  return 0;
}

int bins_command(const RipplesCommands& a) {
  refuse_existing_out(a.out, a.force);
  BinModelRun run;
  if (!a.config.empty()) run = read_bin_model_config(a.config);
  // (As `ripples lattice --ejections` does: `--shots 1000` shortens a preset.)
  auto given = [&](const char* name) { return sets_run(a, a.bin_cmd, name); };
  if (given("--bins")) {
    run.params.bins = a.bins;
  }
  if (given("--shots")) {
    run.shots = a.shots;
  }
  if (given("--seed")) run.params.seed = a.seed;
  const BinModelParams& p = run.params;
  BinModel m(p);
  SampleTable h{
      "h", "surface height (grain diameters) per bin (columns) at each recorded frame (rows)", {}, {}};
  for (int i = 0; i < p.bins; ++i) h.columns.push_back(fmt::format("b{}", i));
  SampleTable history{"history",
                      "per frame: shots fired, rms roughness (grain diameters), dominant wavelength (bins)",
                      {"shots", "roughness", "wavelength"},
                      {}};
  auto record = [&] {
    h.rows.push_back(m.heights());
    history.rows.push_back({double(m.shots_fired()), m.rms_roughness(), m.dominant_wavelength()});
  };
  record();
  if (!a.json)
    fmt::print("Haff's bin model: {} bins of {} grain diameters, shots at {} deg, {} shots\n", p.bins,
               p.bin_width, p.impact_deg, run.shots);
  const long chunk = std::max(1L, run.shots / run.frames);
  for (long done = 0; done < run.shots; done += chunk) {
    m.fire(std::min(chunk, run.shots - done));
    record();
  }
  if (!a.out.empty())
    write_sample_tables(a.out, {h, history},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", "Haff's bin model (thesis Ch. V)"},
                         {"config", run.text.empty() ? "(command-line options)" : run.text},
                         {"units", "heights in grain diameters, x in bins"}});
  if (!a.out.empty()) write_spacetime_plot(a.out, a.force, a.json);
  nlohmann::json hist = nlohmann::json::array();
  for (const auto& row : history.rows)
    hist.push_back({{"shots", row[0]}, {"roughness", row[1]}, {"wavelength", row[2]}});
  if (a.json) {
    fmt::print("{}\n", nlohmann::json{{"history", hist}, {"heights", m.heights()}}.dump(2));
    return 0;
  }
  for (std::size_t k = 0; k < history.rows.size(); k += std::max<std::size_t>(1, history.rows.size() / 10))
    fmt::print("  {:>10.0f} shots: roughness {:.3f} d, dominant wavelength {:.1f} bins\n", history.rows[k][0],
               history.rows[k][1], history.rows[k][2]);
  if (!a.out.empty()) fmt::print("wrote {} (h(x, t): {} frames)\n", a.out, h.rows.size());
  return 0;
}

int wavelength_command(const RipplesCommands& a) {
  // Fig. 5.24's set-up: d = 0.1 cm, reptation length 4 cm, stoss 5 deg, lee 10 deg.
  const double statistical = 0.23, reptation = 4 * std::tan(10 * M_PI / 180);
  nlohmann::json rows = nlohmann::json::array();
  if (!a.json)
    fmt::print(
        "largest ripple from a merger (Fig. 5.24; stoss 5, lee 10 deg, reptation 4 cm):\n{:>6} {:>16} "
        "{:>16}\n",
        "ratio", "statistical (cm)", "reptation (cm)");
  for (const double r : {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9}) {
    const double s = limiting_wavelength(r, statistical), p = limiting_wavelength(r, reptation);
    rows.push_back({{"ratio", r}, {"statistical", s}, {"reptation", p}});
    if (!a.json) fmt::print("{:>6.1f} {:>16.1f} {:>16.1f}\n", r, s, p);
  }
  if (a.json) fmt::print("{}\n", rows.dump(2));
  return 0;
}

}  // namespace

void RipplesCommands::add(CLI::App& app) {
  group = app.add_subcommand("ripples", "the thesis's ripple models (Ch. V)");
  group->require_subcommand(1);
  add_worms();
  add_triangles();
  add_bins();
  add_lattice();
  add_continuum();
  add_run();
  add_analyze();
  add_wavelength();
  add_hybrid_flux();
  add_hybrid_focal();
  add_hybrid();
}

void RipplesCommands::add_worms() {
  chain = group->add_subcommand("worms-chain",
                                "two worms as a Markov chain: exact merger probability and Monte Carlo");
  chain->add_option("--links", links, "links of both worms together (L)")
      ->default_val(10)
      ->check(cli::in_range(2, 1000000));
  chain->add_option("--start", start, "one worm's starting length")->default_val(5);
  chain->add_option("--A", A, "advance probability scale: a worm of l links moves with probability A / l")
      ->default_val(0.6)
      ->check(cli::in_range(0.0, 1.0, Ends::open_low));
  chain->add_option("--steps", steps, "steps")->default_val(416)->check(cli::in_range(0, 100000000));
  chain->add_option("--runs", runs, "Monte Carlo pairs")
      ->default_val(20000)
      ->check(cli::in_range(1, 100000000));
  chain->add_option("--seed", seed, "Monte Carlo seed")->default_val(1);
  chain->add_flag("--json", json, "print {\"absorbed\": P, ...}");
  ring = group->add_subcommand("worms", "Haff's worm model: many worms on a ring merging (Fig. 5.16)");
  ring->add_option("--config", config,
                   "a TOML config with a [worms] table (the options below, where given, replace its values)")
      ->check(CLI::ExistingFile);
  ring->add_option("--out,-o", out, "write the mean-length history and the final lengths to this HDF5 file")
      ->check(cli::output_file());
  ring->add_flag("--force", force, "overwrite --out");
  ring->add_option("--worms", worms, "worms at the start")->default_val(200);
  ring->add_option("--length", length, "links per worm at the start")->default_val(2);
  ring->add_option("--A", A, "advance probability scale")
      ->default_val(0.6)
      ->check(cli::in_range(0.0, 1.0, Ends::open_low));
  ring->add_option("--steps", ring_steps, "steps")->default_val(200000)->check(cli::in_range(0, 100000000));
  ring->add_option("--seed", seed, "seed")->default_val(1);
  ring->add_flag("--json", json, "print the lengths and the mean-length history");
}

void RipplesCommands::add_triangles() {
  triangles = group->add_subcommand("triangles", "two triangular ripples colliding (Figs 5.17-5.20)");
  triangles
      ->add_option(
          "--config", config,
          "a TOML config with a [triangles] table (the options below, where given, replace its values)")
      ->check(CLI::ExistingFile);
  triangles->add_option("--out,-o", out, "write the collision's history to this HDF5 file")
      ->check(cli::output_file());
  triangles->add_flag("--force", force, "overwrite --out");
  triangles->add_option("--ratio", ratio, "upstream / downstream height")
      ->default_val(0.6)
      ->check(cli::in_range(0.0, 1.0, Ends::open));
  triangles->add_option("--law", law, "target or brink transport")
      ->default_val("target")
      ->check(CLI::IsMember({"target", "brink"}));
  triangles->add_option("--beta", beta, "stoss slope, deg")->default_val(5);
  triangles->add_option("--alpha", alpha, "lee slope (impact angle), deg")->default_val(10);
}

void RipplesCommands::add_bins() {
  bin_cmd = group->add_subcommand("bins", "Haff's bin model: shots at a fixed angle, shadowing, repose");
  bin_cmd->add_option("--bins", bins, "bins (periodic)")
      ->default_val(600)
      ->check(cli::in_range(16, 100000000));
  bin_cmd->add_option("--shots", shots, "grains fired")->default_val(2000000)->check(cli::non_negative());
  bin_cmd->add_option("--seed", seed, "seed")->default_val(1);
  bin_cmd
      ->add_option("--config", config,
                   "a TOML config with a [bins] table (the options above, where given, replace its values)")
      ->check(CLI::ExistingFile);
  bin_cmd->add_option("--out,-o", out, "write h(x, t) and the history to this HDF5 file")
      ->check(cli::output_file());
  bin_cmd->add_flag("--force", force, "overwrite --out");
  bin_cmd->add_flag("--json", json, "print the roughness and wavelength history and the final heights");
}

void RipplesCommands::add_lattice() {
  lattice = group->add_subcommand("lattice", "the lattice-bed model (Fig. 5.21): target and brink ejection");
  lattice
      ->add_option("--config", config, "a TOML config with a [lattice] table (scenes/ripples/lattice_*.toml)")
      ->required()
      ->check(CLI::ExistingFile);
  lattice->add_option("--out,-o", out, "write h(x, t) and the history (first seed) to this HDF5 file")
      ->check(cli::output_file());
  lattice
      ->add_option("--ejections", lattice_ejections,
                   "run length in ejections per surface grain (replaces the config's)")
      ->check(cli::in_range(0.0, 1e6, Ends::open_low));  // (so 0 stays "not given")
  lattice->add_option("--seeds", lattice_seeds, "ensemble: the config's seed and the next N - 1")
      ->default_val(1)
      ->check(cli::in_range(1, 100000));
  lattice->add_flag("--force", force, "overwrite --out");
  lattice->add_flag("--json", json, "print the final statistics of every seed and their mean, sd, interval");
}

void RipplesCommands::add_continuum() {
  continuum =
      group->add_subcommand("continuum", "the continuum model: growth rates and steady shapes (eqs 5.3-5.8)");
  continuum->add_option("--speed", shape_speed, "propagation speed of the steady shapes, cm/s")
      ->default_val(0.1)
      ->check(cli::positive());
  continuum->add_option("--out,-o", out, "write the growth rates and the shapes to this HDF5 file")
      ->check(cli::output_file());
  continuum->add_flag("--force", force, "overwrite --out");
  continuum->add_flag("--json", json, "print the growth rates and the shapes' length scale as JSON");
}

void RipplesCommands::add_run() {
  run = group->add_subcommand("run", "any surface-evolving ripple model, named by its config's table");
  run->add_option("--config", config, "a TOML config with one model table ([bins], [lattice])")
      ->check(CLI::ExistingFile);
  run->add_option("--out,-o", out, "write h(x, t) and the history to this HDF5 file")
      ->check(cli::output_file());
  run->add_flag("--force", force, "overwrite --out");
  run->add_flag("--json", json, "print the final diagnostics as JSON");
  run->add_flag("--list", list_models, "list the models");
}

void RipplesCommands::add_analyze() {
  analyze = group->add_subcommand("analyze",
                                  "wavelength, height, ripple index and slopes of any surface (Ch. V tools)");
  analyze
      ->add_option("file", analyze_file,
                   "a CSV of x, h (evenly spaced, periodic) or a ripple run file (bins, lattice, run; "
                   "hybrid: the bed averaged across the wind)")
      ->required()
      ->check(CLI::ExistingFile);
  analyze->add_option("--frame", analyze_frame, "run files: the frame, from 0 (default: the last)")
      ->check(CLI::Validator(
          [](std::string& s) { return s.starts_with('-') ? s + ": frames count from 0" : std::string(); }, "",
          "frame index"));
  analyze->add_option("--smooth", analyze_smooth, "eq. 5.1 smoothing half-width in points (0: none)")
      ->default_val(0)
      ->check(cli::non_negative());
  analyze->add_option("--sigma", analyze_sigma, "eq. 5.1 / 5.2 height scale sigma (the surface's units)")
      ->default_val(1)
      ->check(cli::positive());
  analyze
      ->add_option("--relief", analyze_relief,
                   "least height a crest or trough must stand out by (0: half the rms height)")
      ->default_val(0)
      ->check(cli::non_negative());
  analyze->add_flag("--json", json, "print the results as JSON");
}

void RipplesCommands::add_wavelength() {
  wavelength =
      group->add_subcommand("wavelength", "Fig. 5.24: the largest ripple a merger can make, by size ratio");
  wavelength->add_flag("--json", json, "print the table as JSON");
  triangles->add_flag("--json", json, "print the sizes after the collision and the minimum effective height");
  // The flux model's options, shared by hybrid-flux and hybrid-focal (one of them runs).
}

// The flux model's options, which hybrid-flux and hybrid-focal share.
void RipplesCommands::add_flux_model_options(CLI::App* c) {
  c->add_option("--diameter", flux.diameter, "grain diameter, cm")
      ->default_val(0.025)
      ->check(cli::in_range(1e-5, 10.0));
  c->add_option("--grain-density", flux.grain_density, "g/cm^3")->default_val(2.65)->check(cli::positive());
  c->add_option("--fluid-density", flux.fluid_density, "g/cm^3")
      ->default_val(0.00123)
      ->check(cli::positive());
  c->add_option("--viscosity", flux.viscosity, "kinematic, cm^2/s")
      ->default_val(0.146)
      ->check(cli::positive());
  c->add_option("--length", flux.length, "domain length, grain diameters")
      ->default_val(400)
      ->check(cli::in_range(3.0, 1e6));
  c->add_option("--width", flux.width, "domain width, grain diameters")
      ->default_val(10)
      ->check(cli::in_range(3.0, 1e6));
  c->add_option("--duration", flux.duration, "t* = t / sqrt(d / g^)")
      ->default_val(4000)
      ->check(cli::in_range(1.0, 1e8));
  c->add_option("--average-from", flux.average_from, "start of the averaging window, t*")
      ->default_val(2000)
      ->check(cli::in_range(0.0, 1e8));
  c->add_option("--splash", flux.splash,
                "Lammel parameter set (paper2021, paper2021-effective, lammel2017) or a grainlab-splash/1 "
                "file of recorded impacts (grainlab splash)")
      ->default_val("paper2021")
      ->check(CLI::IsMember(ripples::hybrid::LammelParameters::names()) | CLI::ExistingFile);
  c->add_flag(
      "--no-collisions", [this](std::int64_t) { flux.collisions = false; }, "no mid-air collisions");
  c->add_flag("--collide-within-splash", flux.collide_within_splash,
              "let the grains one splash sends up collide with each other (before 2026-12-03 they did; "
              "docs/hybrid.md)");
  c->add_flag("--wind-loosened", flux.wind_loosened,
              "eq. 19: ejecta need E_eff = E_d2 (1 - tau_fw / tau_ft) (Shao & Lu's threshold)");
  c->add_option("--dead-rise", flux.dead_rise,
                "a rebound or ejectum whose centre cannot rise this many diameters settles")
      ->default_val(1.0)
      ->check(cli::in_range(0.0, 10.0));
  c->add_flag("--swept", flux.swept,
              "find mid-air collisions along the grains' paths over a step and trace impacts back "
              "to the bed's surface, so that --travel may exceed 0.5");
  c->add_flag("--fast-substeps", flux.fast_substeps,
              "with --swept: steps of dt_max, grains faster than travel / dt_max in substeps");
  c->add_option("--travel", flux.travel, "the most a grain moves in a step, d (0.2; 1.5 with --swept)")
      ->default_val(0.2)
      ->check(cli::in_range(0.01, 4.0));
  c->add_option("--dt-max", flux.dt_max,
                "the longest step, sqrt(d / g) (with --fast-substeps every step's length: raise --travel "
                "with it, 1.5 d per 0.02)")
      ->default_val(0.02)
      ->check(cli::in_range(1e-4, 1.0));
  c->add_option("--seed", flux.seed, "seed")->default_val(2021);
}

void RipplesCommands::add_hybrid_flux() {
  hybrid_flux = group->add_subcommand(
      "hybrid-flux", "the 3-D hybrid model's saturated flux over a flat bed (Huo et al. 2021, eq. 31)");
  hybrid_flux->add_option("--ustar", flux.u_star, "wind-shear velocity, cm/s")
      ->default_val(40)
      ->check(cli::in_range(0.1, 1e4));
  add_flux_model_options(hybrid_flux);
  hybrid_flux
      ->add_option("--checkpoint", hybrid_checkpoint,
                   "write the run's state here every --checkpoint-every t*, at --stop-at and at the end")
      ->check(cli::output_file());
  hybrid_flux->add_option("--checkpoint-every", flux.checkpoint_every, "t* between checkpoints")
      ->default_val(1000)
      ->check(cli::positive());
  hybrid_flux->add_option("--stop-at", stop_at, "stop at this t* (needs --checkpoint)")
      ->check(cli::positive());
  hybrid_flux->add_option("--restart", hybrid_restart,
                          "continue a run from its checkpoint (the same options; --duration may be longer)");
  hybrid_flux->add_flag("--json", json, "print the result as JSON");
  hybrid_flux->add_flag("--quiet", quiet, "no progress bar");
}

void RipplesCommands::add_hybrid_focal() {
  hybrid_focal = group->add_subcommand("hybrid-focal",
                                       "the wind over saltation at several u*: the roughness z0 of its log "
                                       "layer and the profiles' focal point "
                                       "(Huo et al. 2021, Fig. 14 and eq. 32)");
  hybrid_focal->add_option("--ustar", focal_ustars, "wind-shear velocities, cm/s (two or more)")
      ->capture_default_str()
      ->check(cli::in_range(0.1, 1e4));
  add_flux_model_options(hybrid_focal);
  hybrid_focal
      ->add_option("--log-band", focal_band,
                   "heights (d) above the saltation layer where the wind is fitted as a log layer")
      ->capture_default_str()
      ->expected(2);
  hybrid_focal
      ->add_option("--focus-above", focal_above, "profiles crossing below this height (d) are ignored")
      ->capture_default_str()
      ->check(cli::in_range(0.0, 1e6));
  hybrid_focal->add_option("--out,-o", out, "a folder for the plots and the profiles (CSV)")
      ->check(cli::output_folder());
  hybrid_focal
      ->add_option("--checkpoint", hybrid_checkpoint,
                   "a folder for each u*'s flux run checkpoint (u<U>.h5, every --checkpoint-every t* and at "
                   "the end); run the same command again to continue")
      ->check(cli::output_folder());
  hybrid_focal->add_option("--checkpoint-every", flux.checkpoint_every, "t* between checkpoints")
      ->default_val(1000)
      ->check(cli::positive());
  hybrid_focal->add_flag("--json", json, "print the result as JSON");
  hybrid_focal->add_flag("--quiet", quiet, "no progress lines");
}

void RipplesCommands::add_hybrid() {
  hybrid_ripples = group->add_subcommand(
      "hybrid", "the 3-D hybrid model's ripple run over an erodible bed (Huo et al. 2021): --config FILE");
  hybrid_ripples->add_option("--config", config, "a [hybrid] config (scenes/ripples/huo2021_ripples.toml)")
      ->required()
      ->check(CLI::ExistingFile);
  hybrid_ripples->add_option("--out", out, "bed history: HDF5 frames + XDMF sidecar, history and flux tables")
      ->check(cli::output_file());
  hybrid_ripples->add_option("--duration", duration_override, "t*, in place of the config's")
      ->check(cli::in_range(1.0, 1e9));  // (so 0 stays "not given")
  hybrid_ripples
      ->add_option("--set", overrides,
                   "KEY=VALUE: a [hybrid] key in place of the config's, VALUE in TOML "
                   "(--set u_star=36 --set splash=lammel2017); repeat for more")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  hybrid_ripples
      ->add_option("--checkpoint", hybrid_checkpoint,
                   "write the run's state here every --checkpoint-every t* (and at --stop-at)")
      ->check(cli::output_file());
  hybrid_ripples->add_option("--checkpoint-every", checkpoint_every, "t* between checkpoints")
      ->default_val(10000)
      ->check(cli::positive());
  hybrid_ripples->add_option("--stop-at", stop_at, "stop after the frame at this t* (needs --checkpoint)")
      ->check(cli::positive());
  hybrid_ripples->add_option(
      "--restart", hybrid_restart,
      "continue a run from its checkpoint (same config; --duration may differ, to go on past the end)");
  hybrid_ripples
      ->add_option("--impacts-from", impacts_from,
                   "log every impact from this t* on into --out's table /impacts (tools/impact_slopes.py "
                   "reads it with the frames; 96 bytes per impact in the file)")
      ->check(cli::non_negative());
  hybrid_ripples->add_flag("--force", force, "overwrite --out");
  hybrid_ripples->add_flag("--json", json, "print the result as JSON");
  hybrid_ripples->add_flag("--quiet", quiet, "no progress bar");
}

int RipplesCommands::dispatch() const {
  if (wavelength && *wavelength) return wavelength_command(*this);
  if (hybrid_flux && *hybrid_flux) return hybrid_flux_command(*this);
  if (hybrid_focal && *hybrid_focal) return hybrid_focal_command(*this);
  if (hybrid_ripples && *hybrid_ripples) return hybrid_ripples_command(*this);
  if (bin_cmd && *bin_cmd) return bins_command(*this);
  if (lattice && *lattice) return lattice_command(*this);
  if (analyze && *analyze) return analyze_command(*this);
  if (run && *run) return run_command(*this);
  if (continuum && *continuum) return continuum_command(*this);
  if (triangles && *triangles) return triangles_command(*this);
  if (chain && *chain) return chain_command(*this);
  if (ring && *ring) return ring_command(*this);
  return -1;
}

}  // namespace grainlab::cli
