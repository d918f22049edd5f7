#include "bench_commands.hpp"

#include <string>

#include "decomposition_options.hpp"
#include "engine_option.hpp"
#include "number_ranges.hpp"
#include "output_path.hpp"
#include "parallel.hpp"
#include "progress.hpp"

namespace grainlab::cli {
namespace {

// Every benchmark repeats its timing and reports the median, and can write its result as JSON.
void add_repeats_and_json(CLI::App* cmd, int& repeats, std::string& json, int default_repeats) {
  cmd->add_option("--repeats", repeats, "timed repetitions (median reported)")
      ->default_val(default_repeats)
      ->check(cli::in_range(1, 100));
  cmd->add_option("--json", json, "also write the result as JSON to this file")->check(cli::output_file());
}

}  // namespace

void BenchCommands::add(CLI::App& app) {
  CLI::App* parent = app.add_subcommand("bench", "benchmarks");
  parent->require_subcommand(1);
  add_bed(parent);
  add_impact(parent);
  add_bed3d(parent);
  add_lattice(parent);
  add_hybrid(parent);
}

void BenchCommands::add_bed(CLI::App* parent) {
  bed_cmd = parent->add_subcommand("bed", "settled disc bed, same work as bench/bed.in for LAMMPS");
  bed_cmd->add_option("--nx", bed.nx, "discs per row")->default_val(100)->check(cli::in_range(1, 100000));
  bed_cmd->add_option("--ny", bed.ny, "rows")->default_val(50)->check(cli::in_range(1, 100000));
  bed_cmd->add_option("--settle", bed.settle_steps, "settling steps (untimed)")
      ->default_val(2000)
      ->check(cli::non_negative());
  bed_cmd->add_option("--steps", bed.timed_steps, "timed steps")->default_val(10000)->check(cli::positive());
  bed_cmd->add_option("--spacing", bed.spacing, "lattice spacing, cm (2.0 with --first-row 1.0: dense bed)")
      ->default_val(2.02)
      ->check(cli::positive());
  bed_cmd->add_option("--first-row", bed.first_row, "height of the first row of centres, cm")
      ->default_val(2.5)
      ->check(cli::positive());
  bed_cmd->add_flag("--frictionless", bed.frictionless, "drop the friction effect (no shear history)");
  cli::add_decomposition_options(bed_cmd, bed.balance_every, bed.ranks_y);
  add_repeats_and_json(bed_cmd, bed.repeats, bed.json, 3);
}

void BenchCommands::add_impact(CLI::App* parent) {
  impact_cmd = parent->add_subcommand(
      "impact", "one Ch. III impact (384 discs, 0.07 s) on one core, beside the impulse engines");
  impact_cmd->add_option("--case", impact.case_name, "A..I")->default_val("A");
  impact_cmd->add_option("--peers", impact.peers, "impulse engines timed on the same impact")
      ->default_str("ode bullet")
      ->check(cli::known_engine())
      ->check(CLI::Validator(
          [](std::string& name) {
            return name == "native" ? std::string("native: is the engine the peers are timed against") : "";
          },
          ""));
  add_repeats_and_json(impact_cmd, impact.repeats, impact.json, 5);
}

void BenchCommands::add_bed3d(CLI::App* parent) {
  bed3d_cmd = parent->add_subcommand(
      "bed3d", "issue #15's sphere lattice in a box of planes, same work as bench/bed3d.in for LAMMPS");
  bed3d_cmd->add_option("--nx", bed3d.nx, "spheres along x")->default_val(20)->check(cli::in_range(1, 10000));
  bed3d_cmd->add_option("--ny", bed3d.ny, "spheres along y")->default_val(20)->check(cli::in_range(1, 10000));
  bed3d_cmd->add_option("--nz", bed3d.nz, "layers")->default_val(6)->check(cli::in_range(1, 10000));
  bed3d_cmd->add_option("--settle", bed3d.settle_steps, "settling steps (untimed)")
      ->default_val(0)
      ->check(cli::non_negative());
  bed3d_cmd->add_option("--steps", bed3d.timed_steps, "timed steps")
      ->default_val(2000)
      ->check(cli::positive());
  CLI::Option* bed3d_scene_flag =
      bed3d_cmd->add_flag("--scene", bed3d.scene_only,
                          "print the bed as a scene (TOML) instead of timing it: grainlab run takes it");
  CLI::Option* pour_to =
      bed3d_cmd
          ->add_option(
              "--pour-to", bed3d.pour_to,
              "pour the NX x NY x NZ spheres into the same box instead of the lattice (untimed) and write "
              "the bed (stopped where the pour leaves it) as BASE.toml (for --bed-scene) and BASE.data "
              "(LAMMPS read_data, "
              "bench/bed3d_data.in); no timing")
          ->check(cli::output_file());
  bed3d_cmd
      ->add_option("--pour-seconds", bed3d.pour_seconds, "--pour-to: simulated settling time of the pour")
      ->default_val(0.3)
      ->check(cli::positive());
  bed3d_cmd
      ->add_option(
          "--bed-scene", bed3d.bed_scene,
          "time this 3-D scene (e.g. a --pour-to bed) instead of the lattice; --nx/--ny/--nz are not "
          "used")
      ->check(CLI::ExistingFile)
      ->excludes(pour_to)
      ->excludes(bed3d_scene_flag);
  add_repeats_and_json(bed3d_cmd, bed3d.repeats, bed3d.json, 3);
}

void BenchCommands::add_lattice(CLI::App* parent) {
  lattice_cmd = parent->add_subcommand(
      "lattice", "impacts per second of the lattice-bed ripple model (Fig. 5.21) on one core");
  lattice_cmd->add_option("--columns", lattice.columns, "lattice columns (even)")
      ->default_val(10000)
      ->check(cli::in_range(16, 100000000));
  lattice_cmd->add_option("--warmup", lattice.warmup, "ejections per surface grain before timing ripples")
      ->default_val(100)
      ->check(cli::in_range(0.0, 1e6));
  lattice_cmd->add_option("--timed", lattice.timed, "ejections per surface grain timed")
      ->default_val(20)
      ->check(cli::in_range(0.01, 1e6));
  add_repeats_and_json(lattice_cmd, lattice.repeats, lattice.json, 5);
}

void BenchCommands::add_hybrid(CLI::App* parent) {
  hybrid_cmd = parent->add_subcommand(
      "hybrid", "airborne grain-steps per second of the 3-D hybrid ripple model's flux run on one core");
  hybrid_cmd->add_option("--length", hybrid.length, "domain length, grain diameters")
      ->default_val(400)
      ->check(cli::in_range(3.0, 1e6));
  hybrid_cmd->add_option("--width", hybrid.width, "domain width, grain diameters")
      ->default_val(10)
      ->check(cli::in_range(3.0, 1e6));
  hybrid_cmd->add_option("--ustar", hybrid.u_star, "cm/s")
      ->default_val(40)
      ->check(cli::in_range(20.0, 500.0));
  hybrid_cmd->add_option("--duration", hybrid.duration, "t* per run")
      ->default_val(1000)
      ->check(cli::in_range(10.0, 1e7));
  add_repeats_and_json(hybrid_cmd, hybrid.repeats, hybrid.json, 3);
}

int BenchCommands::dispatch() {
  if (*bed_cmd) return bench::run_bed_command(bed);
  if (*impact_cmd) return bench::run_impact_bench(impact);
  if (*lattice_cmd) return bench::run_lattice_bench(lattice);
  if (*hybrid_cmd) return bench::run_hybrid_bench(hybrid);
  if (*bed3d_cmd) {
    cli::ProgressBar bar(parallel::rank() == 0);  // (the pour's: stderr, so stdout keeps the results)
    bed3d.progress = [&bar](double done, double total) { bar.update(done, total); };
    return bench::run_bed3d_bench(bed3d);
  }
  return -1;
}

}  // namespace grainlab::cli
