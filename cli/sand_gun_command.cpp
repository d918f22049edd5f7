#include "sand_gun_command.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "active_zone_option.hpp"
#include "input_error.hpp"
#include "number_ranges.hpp"
#include "option_scope.hpp"
#include "output_path.hpp"
#include "parallel.hpp"
#include "progress.hpp"
#include "sand_gun3d.hpp"
#include "sand_gun_plots.hpp"

namespace grainlab::cli {

namespace {

using namespace grainlab::validation;

nlohmann::json number(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

nlohmann::json run_json(const SandGunCommand& a, const SandGunRun& run) {
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < run.rows.size(); ++i) {
    const SandGunRow& row = run.rows[i];
    nlohmann::json q;
    for (const auto& [k, m] : run.quantities[i]) {
      q[k] = {{"mean", number(m.mean)},
              {"lo", number(m.lo)},
              {"hi", number(m.hi)},
              {"sd", number(m.sd)},
              {"n", m.n}};
      if (row.measured.count(k)) q[k]["experiment"] = row.measured.at(k);
    }
    rows.push_back({{"row", row.index},
                    {"speed", row.speed},
                    {"alpha", row.alpha_deg},
                    {"impacts", run.impacts[i].size()},
                    {"events_in_experiment", row.events},
                    {"quantities", q}});
  }
  nlohmann::json exponents;
  if (sand_gun_speed_series(run).size() >= 2)
    for (const char* k : {"ejecta", "ej_vz", "reptation"}) {
      const auto [ours, theirs] = sand_gun_exponent(run, k);
      exponents[k] = {{"exponent", number(ours.exponent)},
                      {"half_width", number(ours.half_width)},
                      {"experiment", number(theirs.exponent)}};
    }
  const Bed3dSpec& s = run.bed.spec;
  return {{"spheres", run.bed.scene.bodies3d.size()},
          {"spheres_removed", run.bed.removed},
          {"bed_top", run.bed.top},
          {"packing_fraction", run.bed.packing_fraction},
          {"bed_seconds", run.bed.build_seconds},
          {"bed_probes", run.bed.probes},
          {"bed_holds", build_holds(run.bed)},
          {"bed_still_moving", run.bed.deep_movers},
          {"k_n", s.k_n},
          {"grains", s.polyhedra ? "polyhedron" : "sphere"},
          {"seed", a.seed},
          {"bed_seed", a.bed_seed},
          {"runs", a.runs},
          {"active_zone", a.active_zone},
          {"visible_above", run.visible_above},
          {"rows", rows},
          {"exponents", exponents}};
}

}  // namespace

void SandGunCommand::add(CLI::App& app) {
  cmd = app.add_subcommand(
      "sand-gun", "the thesis's sand-gun experiment (Tables 3.11-3.12) with spheres of a sieved sand");
  cmd->add_option("--spheres", spheres,
                  "spheres in the sand bed (20,000: 5.0 x 2.5 cm, about 10 grains deep)")
      ->default_val(20000)
      ->check(cli::in_range(500, 1000000));
  cmd->add_option("--rows", rows, "the tables' rows to shoot, 1-9 (default: all)")
      ->check(cli::in_range(1, 9));
  cmd->add_option("--runs", runs, "impacts per row (spread over MPI ranks); 0: build the bed only")
      ->default_val(20)
      ->check(cli::in_range(0, 100000));
  cmd->add_option("--seed", seed, "seed: impact i draws its point from (seed, i)")->default_val(1);
  cmd->add_option("--bed-seed", bed_seed, "seed of the pour")->default_val(1);
  cmd->add_option("--stiffness", stiffness, "k_n as a multiple of the default 2e7 dyn/cm")
      ->default_val(1)
      ->check(cli::in_range(0.01, 100.0));
  cmd->add_option(
         "--grains", grains,
         "sphere, or polyhedron: irregular convex grains of the spheres' volumes (the general 3-D "
         "path, 60-80 times slower: a 5,000-grain bed took 5.6 hours on one core, so use --checkpoint; "
         "it uses every core, or OMP_NUM_THREADS of them)")
      ->default_val("sphere")
      ->check(CLI::IsMember({"sphere", "polyhedron"}));
  cmd->add_option("--checkpoint", checkpoint,
                  "keep the bed (after each stage of its build, and every 10 min within one) and each "
                  "finished impact in this HDF5 file; run again with it to continue (more --runs or other "
                  "--rows may be asked for)")
      ->check(cli::output_file());
  add_active_zone_option(cmd, active_zone);
  cmd->add_option("--visible-above", visible_above,
                  "count an ejectum only if its centre rises this many bed-grain diameters above the top of "
                  "the bed (1: the thesis's rule; the photographs' apparent surface stood a few diameters "
                  "above the true one)")
      ->default_val(1.0)
      ->check(cli::in_range(1.0, 50.0));
  cmd->add_option("--plots", plots,
                  "draw the tables' ejecta, ejection speed, reptation and rebound angle against v_i, beside "
                  "the experiment, into this folder (PNG, with Debian's matplotlib)")
      ->check(cli::output_folder());
  cmd->add_flag("--json", json, "print one JSON object (rows, quantities with intervals, exponents)");
  cmd->add_flag("--quiet,-q", quiet, "no progress");
}

int SandGunCommand::dispatch() const {
  if (!cmd || !*cmd) return -1;
  if (runs == 0)  // the bed only: refused before its build, which takes minutes to hours
    for (const char* name : {"--rows", "--seed", "--active-zone", "--visible-above", "--plots"})
      refuse_if_given(cmd->get_option(name), "is for impacts; --runs 0 builds the bed only");
  const bool speak = !quiet && parallel::rank() == 0;  // (stderr: kept with --json)
  Bed3dSpec spec = sand_gun_bed_spec(spheres, stiffness);
  spec.seed = bed_seed;
  spec.polyhedra = grains == "polyhedron";
  ProgressBar bar(!quiet && parallel::rank() == 0, "impacts");  // (stderr: kept with --json)
  SandGunRun run = run_sand_gun(
      spec, rows, runs, seed,
      [&](const std::string& line) {
        if (!speak) return;
        bar.finish();
        fmt::print(stderr, "grainlab {}\n", line);
      },
      [&](std::size_t d, std::size_t t) { bar.update(static_cast<double>(d), static_cast<double>(t)); },
      checkpoint, active_zone);
  bar.finish();
  if (parallel::rank() != 0) return 0;
  if (runs == 0) {  // the bed only
    const Bed3d& bed = run.bed;
    if (json)
      fmt::print("{}\n", run_json(*this, run).dump(2));
    else
      fmt::print("sand bed of {} grains built: top {:.3f} cm, packing {}{}\n", bed.scene.bodies3d.size(),
                 bed.top, packing_text(bed),
                 checkpoint.empty() ? "" : fmt::format(", kept in {}", checkpoint));
    return 0;
  }
  if (visible_above != 1) recount_sand_gun(run, visible_above);
  if (!plots.empty()) {
    write_plots(sand_gun_plots(run), plots);
    fmt::print(json ? stderr : stdout, "drew the tables' figures in {}/ (sand_gun_*.png)\n", plots);
  }
  if (json) {
    fmt::print("{}\n", run_json(*this, run).dump(2));
    return 0;
  }
  fmt::print("{}", sand_gun_markdown(run));
  return 0;
}

}  // namespace grainlab::cli
