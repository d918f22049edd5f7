// grainlab: the command line. Subcommands: run, inspect, validate, cost, engines, die-model, bench, bed,
// impact, rebound-model, splash, saltation, ripples.
// Exit status: 0 success; 1 a check failed or a simulation broke down; 2 bad input (nothing written).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "accuracy_cost.hpp"
#include "bench_commands.hpp"
#include "binary_fingerprint.hpp"
#include "decomposition_options.hpp"
#include "die_model_command.hpp"
#include "domain.hpp"
#include "engine.hpp"
#include "engine_option.hpp"
#include "finite_numbers.hpp"
#include "h5_input.hpp"
#include "h5_output.hpp"
#include "impact_commands.hpp"
#include "input_error.hpp"
#include "inspect_command.hpp"
#include "number_ranges.hpp"
#include "output_path.hpp"
#include "parallel.hpp"
#include "progress.hpp"
#include "ranks.hpp"
#include "ripples_commands.hpp"
#include "saltation_commands.hpp"
#include "sand_gun_command.hpp"
#include "scene.hpp"
#include "suites.hpp"
#include "validate_command.hpp"

namespace fs = std::filesystem;
using namespace grainlab;

namespace {

struct RunArgs {
  std::string scene, out, engine = "native", checkpoint, restart;
  std::vector<std::string> sets;
  bool force = false, quiet = false;
  int checkpoint_every = 0, stop_after_frame = 0;
  std::uint64_t balance_every = dem::kBalanceEveryDefault;
  int ranks_y = 1;
};

// The engine for this process: under mpirun the native 2-D engine spreads the scene over every rank;
// a scene it cannot spread yet runs on rank 0 alone (the others get none and stop).
std::unique_ptr<Engine> engine_for_run(const RunArgs& a, const Scene& scene) {
  if (parallel::size() == 1) return make_engine(a.engine, scene);
  if (parallel::size() % a.ranks_y != 0)
    throw InputError(
        {"--ranks-y", 0}, std::to_string(a.ranks_y),
        fmt::format("{} MPI ranks cannot form a grid with {} rows", parallel::size(), a.ranks_y));
  const std::string why = why_not_distributed(a.engine, scene);
  if (why.empty()) return make_distributed_native_engine(scene, a.balance_every, a.ranks_y);
  if (parallel::rank() != 0) return nullptr;
  if (!a.quiet)
    fmt::print(stderr, "grainlab run: note: {}; rank 0 runs the whole scene, {}\n", why,
               cli::other_ranks_stop(parallel::size()));
  return make_engine(a.engine, scene);
}

int run_command(const RunArgs& a) {
  // Every rank reads and checks the input, so every rank exits 2 alike on bad input.
  const Scene scene = load_scene(a.scene, a.sets);
  std::string out = a.out.empty() ? scene.output.file : a.out;
  if (out.empty()) out = fs::path(a.scene).stem().string() + ".h5";
  // The scene's own output file (an --out was checked when the command line was read).
  if (a.out.empty()) cli::check_output_path("[output] file", out, false);
  if (!a.force && fs::exists(out) && a.stop_after_frame == 0)
    throw InputError({"--out", 0}, out, "exists; pass --force to overwrite it");
  if (a.stop_after_frame > scene.output.frames)
    throw InputError({"--stop-after-frame", 0}, std::to_string(a.stop_after_frame),
                     fmt::format("the scene has only {} frames", scene.output.frames));
  // A checkpoint file alone writes nothing: say so rather than let a long run end without one.
  if (!a.checkpoint.empty() && a.checkpoint_every == 0 && a.stop_after_frame == 0)
    throw InputError({"--checkpoint", 0}, a.checkpoint,
                     "names the file that --checkpoint-every or --stop-after-frame writes; give one of them");
  auto engine = engine_for_run(a, scene);
  if (!engine) return 0;
  const bool speak = !a.quiet && parallel::rank() == 0;
  if (speak)
    fmt::print(stderr, "grainlab run: {} ({} bodies, {} s) on {} [{}]{}, effects: {}\n", scene.name,
               static_cast<long>(engine->diagnostics().at("particles")), scene.duration, engine->name(),
               engine->integrator(),
               engine->ranks() > 1 ? fmt::format(" over {} MPI ranks", engine->ranks()) : std::string(),
               fmt::join(scene.effects.names(), ", "));
  else
    engine->diagnostics();  // collective in a distributed engine: every rank takes part
  cli::ProgressBar bar(speak);
  RunOptions opt{out, a.force, [&](double t, double total) { bar.update(t, total); }};
  opt.write = parallel::rank() == 0;
  opt.checkpoint_every = a.checkpoint_every;
  opt.checkpoint =
      a.checkpoint.empty() ? fs::path(out).replace_extension(".checkpoint.h5").string() : a.checkpoint;
  opt.stop_after_frame = a.stop_after_frame;
  opt.restart = a.restart;
  const RunSummary s = run_scene(scene, *engine, opt);
  bar.finish();
  if (!speak) return 0;
  if (s.stopped) {
    fmt::print(stderr, "stopped after frame {} as asked; continue with --restart {}\n", a.stop_after_frame,
               opt.checkpoint);
    return 0;
  }
  const auto& d = s.diagnostics;
  if (s.restarted_from_frame > 0)
    fmt::print(stderr, "continued from frame {} of {}\n", s.restarted_from_frame, a.restart);
  fmt::print(stderr, "wrote {} and {}\n", s.h5, s.xmf);
  fmt::print(
      stderr,
      "steps {:.0f} (rejected {:.0f}), force evaluations {:.0f}, contacts at end {:.0f}, wall {:.2f} s\n",
      d.at("steps"), d.at("rejected_steps"), d.at("force_evaluations"), d.at("contacts"),
      d.at("wall_seconds"));
  fmt::print(stderr, "energy: initial {:.6g}, final {:.6g} ({})\n", s.initial.total(), s.final.total(),
             scene.units == "si" ? "J" : "erg");
  return 0;
}

// How `run` and `bench bed` spread a scene over MPI ranks.
// The finished scenes' rows of a cost study, kept in OUT/.cost-checkpoint.json until the report is
// written, with a stamp of what made them (quick or full, repeats, this binary): `cost --resume` takes a
// scene from it instead of measuring it again. Each scene's timings come from one sitting, so the ratios
// within a scene, which the study is about, are never mixed across sittings.
class CostCheckpoint {
 public:
  CostCheckpoint(const std::string& out, const validation::CostOptions& o, bool resume)
      : path_((fs::path(out) / ".cost-checkpoint.json").string()),
        stamp_(fmt::format("quick {} repeats {} binary {:016x}", o.quick, o.repeats, binary_fingerprint())) {
    fs::create_directories(out);
    if (!resume) {
      fs::remove(path_);  // a stale checkpoint must not be taken by a later --resume
      return;
    }
    if (!fs::exists(path_)) return;
    try {
      std::ifstream in(path_);
      const nlohmann::json j = nlohmann::json::parse(in);
      if (j.at("stamp") != stamp_) {
        fmt::print(stderr, "{}: made by another binary or other options; measuring every scene\n", path_);
        return;
      }
      for (const auto& [scene, rows] : j.at("scenes").items())
        for (const auto& r : rows) scenes_[scene].push_back(validation::cost_row_from_json(r));
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: unreadable ({}); measuring every scene\n", path_, e.what());
      scenes_.clear();
    }
  }
  void attach(validation::CostOptions& o) {
    o.taken = [this](const std::string& scene) -> std::optional<std::vector<validation::CostRow>> {
      const auto it = scenes_.find(scene);
      if (it == scenes_.end()) return std::nullopt;
      return it->second;
    };
    o.finished = [this](const std::string& scene, const std::vector<validation::CostRow>& rows) {
      scenes_[scene] = rows;
      nlohmann::json j{{"stamp", stamp_}, {"scenes", nlohmann::json::object()}};
      for (const auto& [name, list] : scenes_)
        for (const auto& r : list) j["scenes"][name].push_back(validation::cost_row_json(r, true));
      write_file_atomically(path_, j.dump(1) + "\n");
    };
  }
  void clear() const { fs::remove(path_); }

 private:
  std::string path_, stamp_;
  std::map<std::string, std::vector<validation::CostRow>> scenes_;
};

int cost_command(validation::CostOptions o, const std::string& out, bool quiet, bool resume) {
  cli::check_output_path("--out", out, true);  // the default, which the option's own check does not see
  const std::vector<validation::CostScene> scenes = validation::cost_scenes(o.quick);
  for (const std::string& n : o.scenes) {
    bool known = false;
    std::string names;
    for (const auto& s : scenes) known |= s.name == n, names += (names.empty() ? "" : ", ") + s.name;
    if (!known) throw InputError({"--scene", 0}, n, "unknown cost scene; known scenes: " + names);
  }
  if (!quiet) o.log = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
  CostCheckpoint checkpoint(out, o, resume);
  checkpoint.attach(o);
  const auto rows = validation::run_cost_study(o);
  validation::write_cost_report(rows, scenes, out, o.quick);
  checkpoint.clear();
  fmt::print("{} settings measured; {}/cost.md and {}/cost.json\n", rows.size(), out, out);
  return 0;
}

int engines_command(bool json) {
  if (json) {
    nlohmann::json j = nlohmann::json::array();
    for (const Capabilities& c : engine_catalog())
      j.push_back({{"name", c.name},
                   {"description", c.description},
                   {"dimensions", c.dimensions},
                   {"shapes", c.shapes},
                   {"effects", c.effects},
                   {"periodic", c.periodic},
                   {"generated_assemblies", c.generated_assemblies},
                   {"max_polygon_vertices", c.max_polygon_vertices},
                   {"contact_model", c.contact_model},
                   {"contact_events", c.contact_events}});
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  for (const Capabilities& c : engine_catalog()) {
    fmt::print("{}: {}\n", c.name, c.description);
    fmt::print("  dimensions {}; shapes: {}; effects: {}; periodic: {}\n", fmt::join(c.dimensions, " and "),
               fmt::join(c.shapes, ", "), fmt::join(c.effects, ", "), c.periodic ? "yes" : "no");
    fmt::print("  contacts: {}\n", c.contact_model);
    fmt::print("  contact events: {}\n", c.contact_events);
  }
  return 0;
}

// `grainlab run`'s options into `run`.
CLI::App* add_run_command(CLI::App& app, RunArgs& run) {
  CLI::App* run_cmd = app.add_subcommand("run", "run a scene and write HDF5 frames (+ XDMF for ParaView)");
  run_cmd->add_option("scene", run.scene, "scene file (TOML, see docs/scenes.md)")
      ->required()
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--out,-o", run.out, "output .h5 (default: [output] file, or SCENE.h5)")
      ->check(cli::output_file());
  run_cmd->add_option("--set", run.sets, "override a scene value: --set accuracy.dt=1e-6 (repeatable)");
  cli::add_engine_option(run_cmd, run.engine, "engine to run on");
  run_cmd->add_flag("--force", run.force, "overwrite an existing output file");
  run_cmd->add_flag("--quiet,-q", run.quiet, "no progress bar or summary");
  run_cmd
      ->add_option("--checkpoint-every", run.checkpoint_every,
                   "write a checkpoint after every N-th frame (native engine: 2-D discs, 3-D under Verlet)")
      ->check(cli::non_negative());
  run_cmd->add_option("--checkpoint", run.checkpoint, "checkpoint file (default: OUT with .checkpoint.h5)")
      ->check(cli::output_file());
  run_cmd->add_option("--restart", run.restart, "continue from this checkpoint file")
      ->check(CLI::ExistingFile);
  run_cmd
      ->add_option("--stop-after-frame", run.stop_after_frame,
                   "stop after frame N with a checkpoint, writing no run file (continue with --restart)")
      ->check(cli::non_negative());
  cli::add_decomposition_options(run_cmd, run.balance_every, run.ranks_y);
  return run_cmd;
}

struct CostArgs {
  validation::CostOptions options;
  std::string dir = "cost";
  bool quiet = false, resume = false;
};

CLI::App* add_cost_command(CLI::App& app, CostArgs& cost) {
  CLI::App* cost_cmd = app.add_subcommand(
      "cost", "what accuracy costs: sweep every engine's accuracy knobs, error against time per scene");
  cost_cmd->add_flag("--quick", cost.options.quick, "fewer settings, fewer throws (for CI)");
  cost_cmd->add_option("--out,-o", cost.dir, "output folder (cost.md, cost.json, plots)")
      ->default_val("cost")  // before the check: a default is checked where it is set, at every start
      ->check(cli::output_folder());
  cost_cmd->add_option("--repeats", cost.options.repeats, "timed repetitions per setting (median reported)")
      ->default_val(3)
      ->check(cli::in_range(1, 100));
  cost_cmd->add_option("--scene", cost.options.scenes, "scene to study (repeatable; default: all)");
  cost_cmd->add_flag("--quiet,-q", cost.quiet, "no progress lines");
  cost_cmd->add_flag(
      "--resume", cost.resume,
      "continue an interrupted study into the same --out: the scenes it finished (same options, "
      "same binary) are taken from OUT/.cost-checkpoint.json, the rest measured");
  return cost_cmd;
}

CLI::App* add_die_model_command(CLI::App& app, cli::DieModelArgs& die) {
  CLI::App* die_cmd = app.add_subcommand(
      "die-model", "the thesis's loaded 2-D die model (Appendix II.1): probability p_h of a high face up");
  die_cmd->add_option("--f", die.f, "loading: fraction of the way from centre to corner")
      ->default_val(0.2)
      ->check(cli::in_range(0.0, 1.0, cli::Ends::open_high));
  die_cmd->add_option("--eps", die.eps, "die-plane coefficient of restitution")
      ->default_val(0.7)
      ->check(cli::in_range(0.0, 1.0, cli::Ends::open_high));
  die_cmd->add_flag("--json", die.json, "machine-readable");
  die_cmd->add_option("--plot", die.plot_dir,
                      "also write p_h(f) for several eps (Fig. 2.7) into this folder");
  return die_cmd;
}

// Parses the command line: the exit status when it is done (help, version, a parse error), else nothing.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  parallel::init_if_launched(&argc, &argv);
  struct Finalize {
    ~Finalize() { parallel::finalize(); }
  } finalize_mpi;
  CLI::App app{"grainlab: grain-scale physics of wind-blown sand (Werner 1987), checked across engines"};
  app.require_subcommand(1);
  app.set_version_flag("--version", GRAINLAB_VERSION);

  RunArgs run;
  CLI::App* run_cmd = add_run_command(app, run);
  cli::ValidateCommand validate;
  validate.add(app);
  CostArgs cost;
  CLI::App* cost_cmd = add_cost_command(app, cost);

  std::string inspect_path;
  CLI::App* inspect_cmd = app.add_subcommand("inspect",
                                             "read a file grainlab wrote back (a run, a splash file, a file "
                                             "of tables) and check every part (exit 2 if "
                                             "truncated or damaged)");
  inspect_cmd->add_option("file", inspect_path, "the .h5 file")->required();

  bool engines_json = false;
  CLI::App* engines_cmd = app.add_subcommand("engines", "list the engines and what each can simulate");
  engines_cmd->add_flag("--json", engines_json, "machine-readable");

  cli::DieModelArgs die;
  CLI::App* die_cmd = add_die_model_command(app, die);
  cli::BenchCommands bench;
  bench.add(app);
  cli::ImpactCommands impacts;
  impacts.add(app);
  cli::SandGunCommand sand_gun;
  sand_gun.add(app);
  cli::SaltationCommands saltation;
  saltation.add(app);
  cli::RipplesCommands ripples;
  ripples.add(app);
  if (const std::optional<int> status = parse_command_line(app, argc, argv)) return *status;

  try {
    if (const std::string command = cli::chosen_command(app);
        parallel::size() > 1 && !cli::command_uses_ranks(command)) {
      if (parallel::rank() != 0) return 0;
      fmt::print(stderr, "grainlab {}: note: runs on one process; {}\n", command,
                 cli::other_ranks_stop(parallel::size()));
    }
    cli::refuse_non_finite_numbers(app);
    if (*run_cmd) return run_command(run);
    if (const int status = validate.dispatch(); status >= 0) return status;
    if (*engines_cmd) return engines_command(engines_json);
    if (*cost_cmd) return cost_command(cost.options, cost.dir, cost.quiet, cost.resume);
    if (*inspect_cmd) return cli::inspect_command(inspect_path);
    if (*die_cmd) return cli::die_model_command(die);
    if (const int status = bench.dispatch(); status >= 0) return status;
    if (const int status = impacts.dispatch(); status >= 0) return status;
    if (const int status = sand_gun.dispatch(); status >= 0) return status;
    if (const int status = saltation.dispatch(); status >= 0) return status;
    if (const int status = ripples.dispatch(); status >= 0) return status;
  } catch (const InputError& e) {
    fmt::print(stderr, "grainlab: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    // Bad input is refused by every rank alike (above); any other failure may be one rank's alone.
    fmt::print(stderr, "grainlab: failed: {}\n", e.what());
    parallel::abort_all(1);
    return 1;
  }
  return 0;
}
